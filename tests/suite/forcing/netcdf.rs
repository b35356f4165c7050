//! NetCDF files: the trajectory file read back (fill values outside a
//! floe's life), and the NetCDF-4 fixtures of `tests/data/netcdf4` read as
//! their classic twin, packed variables unpacked, a missing variable
//! refused.

use super::{case, regular};
use crate::common::{case_path, load, run, tempdir};
use floebench::formulation::load_case;
use floebench::model::forcing::GridData;
use floebench::model::netcdf::{read_grid, GridRequest};
use floebench::run::netcdf_out::{read_trajectory, write_trajectory};
use floebench::run::EndReason;
use std::path::Path;

#[test]
fn the_trajectory_netcdf_file_reads_back_with_fill_values_outside_a_floes_life() {
    let dir = tempdir();
    let row = |t: f64, floe: usize, k: f64| floebench::run::TrajectoryRow {
        t,
        floe,
        x: k,
        y: -k,
        theta: 0.1 * k,
        vx: 1e-3 * k,
        vy: -2e-3 * k,
        omega: 1e-5 * k,
    };
    // Floe 0 ends after t = 1 (fracture into 1 and 2, born at t = 2).
    let rows = vec![
        row(0.0, 0, 1.0),
        row(1.0, 0, 2.0),
        row(2.0, 1, 3.0),
        row(2.0, 2, 4.0),
        row(3.0, 1, 5.0),
        row(3.0, 2, 6.0),
    ];
    let path = dir.path().join("trajectory.nc");
    write_trajectory(&path, &rows, "test", Some("2024-03-01 00:00:00")).unwrap();
    let back = read_trajectory(&path).unwrap();
    assert_eq!(back.time, vec![0.0, 1.0, 2.0, 3.0]);
    assert_eq!(back.floe, vec![0, 1, 2]);
    assert_eq!(back.time_units, "seconds since 2024-03-01 00:00:00");
    let names: Vec<&str> = back.variables.iter().map(|v| v.0.as_str()).collect();
    assert_eq!(names, ["x", "y", "theta", "vx", "vy", "omega"]);
    let x = &back.variables[0].2;
    assert_eq!(
        x,
        &vec![
            Some(1.0),
            None,
            None,
            Some(2.0),
            None,
            None,
            None,
            Some(3.0),
            Some(4.0),
            None,
            Some(5.0),
            Some(6.0),
        ]
    );
    assert_eq!(back.variables[5].1, "rad s-1");
    assert_eq!(back.variables[5].2[11], Some(1e-5 * 6.0));
    // A run written by the CLI's writer reads back to its trajectory.csv rows.
    let scn = load("gridded_drift");
    let r = run(&scn, "free-drift");
    let out = floebench::run::output::write_netcdf(dir.path(), &r, &scn).unwrap();
    let back = read_trajectory(&out).unwrap();
    assert_eq!(back.time_units, "seconds since 2024-03-01 00:00:00");
    let nf = back.floe.len();
    for row in &r.trajectory {
        let k = back.time.iter().position(|&t| t == row.t).unwrap();
        let j = back.floe.iter().position(|&f| f == row.floe).unwrap();
        let got: Vec<f64> = back
            .variables
            .iter()
            .map(|v| v.2[k * nf + j].unwrap())
            .collect();
        assert_eq!(
            got,
            vec![row.x, row.y, row.theta, row.vx, row.vy, row.omega]
        );
    }
}

/// `tests/data/netcdf4/<name>`: the NetCDF-4 fixtures written by
/// `tests/data/netcdf4/make_fixtures.py` from `cases/gridded_drift.nc`.
fn netcdf4_fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/netcdf4")
        .join(name)
}

/// The gridded case's request for `variables` (its air or its water).
fn gridded_request(variables: [&str; 2]) -> GridRequest {
    GridRequest {
        variables: variables.map(String::from),
        origin: Some([0.0, 79.0]),
        start: Some("2024-03-01 00:00:00".into()),
    }
}

/// The gridded case's air and water fields (`u10`/`v10`, `uo`/`vo`) read
/// from `cases/gridded_drift.nc` and from the fixture `name`.
fn classic_and_fixture(name: &str) -> Vec<([&str; 2], GridData, GridData)> {
    let classic = case_path("gridded_drift").with_file_name("gridded_drift.nc");
    [["u10", "v10"], ["uo", "vo"]]
        .into_iter()
        .map(|vars| {
            let req = gridded_request(vars);
            let read = |p: &Path| read_grid(p, &req).unwrap_or_else(|e| panic!("{e}"));
            (vars, read(&classic), read(&netcdf4_fixture(name)))
        })
        .collect()
}

#[test]
fn a_netcdf4_file_gives_the_classic_files_field_bit_for_bit() {
    // The NetCDF-4 twin of cases/gridded_drift.nc: chunked, deflate +
    // shuffle, int32 hours since 1900, latitudes decreasing, a depth level
    // on uo/vo, values stored as doubles. The field read must be the
    // classic file's exactly (nodes, times, values, epoch): the field at
    // every point is a function of these alone.
    for (vars, a, b) in classic_and_fixture("gridded_drift_nc4.nc") {
        assert_eq!((a.x.len(), a.y.len(), a.t.len()), (13, 9, 5));
        assert_eq!(a, b, "{vars:?}");
    }
}

#[test]
fn a_netcdf4_file_gives_the_classic_files_trajectory_bit_for_bit() {
    let text = std::fs::read_to_string(case_path("gridded_drift")).unwrap();
    let classic = load("gridded_drift");
    // The same case beside the NetCDF-4 twin.
    let twin = text.replace(
        "file = \"gridded_drift.nc\"",
        "file = \"gridded_drift_nc4.nc\"",
    );
    assert_ne!(twin, text);
    let twin = floebench::formulation::parse_case(&twin, &netcdf4_fixture("twin.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let (a, b) = (run(&classic, "free-drift"), run(&twin, "free-drift"));
    assert_eq!(a.summary.end, EndReason::Completed, "{:?}", a.summary.end);
    assert!(a.trajectory.len() > 3 * 70, "{}", a.trajectory.len());
    assert_eq!(a.trajectory, b.trajectory);
}

#[test]
fn a_packed_netcdf4_file_is_unpacked_to_within_half_its_scale_factor() {
    // ERA5's packing: int16 with scale_factor and add_offset, fill -32767.
    // The script packs each variable over its range, so the scale factor
    // is (max − min)/65532 and the unpacked values are within half of it.
    for (vars, a, b) in classic_and_fixture("gridded_drift_nc4_packed.nc") {
        assert_eq!((&a.x, &a.y, &a.t, a.epoch), (&b.x, &b.y, &b.t, b.epoch));
        for (name, exact, unpacked) in [(vars[0], &a.u, &b.u), (vars[1], &a.v, &b.v)] {
            let max = exact.iter().copied().fold(f64::MIN, f64::max);
            let min = exact.iter().copied().fold(f64::MAX, f64::min);
            let half = 0.5 * (max - min) / 65532.0;
            let worst = exact
                .iter()
                .zip(unpacked)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            // (rounding to int16 leaves up to half a step; 1e-9 of it for
            // the f64 arithmetic of packing and unpacking)
            assert!(worst <= half * (1.0 + 1e-9), "{name}: {worst:e} > {half:e}");
            if half > 0.0 {
                assert!(worst > 0.0, "{name}: not packed?");
            }
        }
    }
}

#[test]
fn a_netcdf4_file_without_a_variable_is_refused_naming_the_file_and_the_variable() {
    let text = std::fs::read_to_string(case_path("gridded_drift"))
        .unwrap()
        .replace(
            "file = \"gridded_drift.nc\"",
            "file = \"missing_variable_nc4.nc\"",
        );
    let e = floebench::formulation::parse_case(&text, &netcdf4_fixture("bad.toml"))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("missing_variable_nc4.nc") && e.contains("no variable `v10`"),
        "{e}"
    );
    // A truncated NetCDF-4 file: refused as NetCDF-4 that cannot be read.
    let dir = tempdir();
    let bytes = std::fs::read(netcdf4_fixture("gridded_drift_nc4.nc")).unwrap();
    std::fs::write(dir.path().join("g.nc"), &bytes[..bytes.len() / 3]).unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(
        &path,
        case(
            "water = { density = 1024.0, drag = 5.0e-3, field = \"netcdf\", file = \"g.nc\", origin = [0.0, 79.0] }",
            3600.0,
            &regular(0.0, 0.0, 50.0, 6),
        ),
    )
    .unwrap();
    let e = load_case(&path).unwrap_err().to_string();
    assert!(
        e.contains("g.nc")
            && (e.contains("is NetCDF-4 (HDF5) but cannot be read")
                || e.contains("cannot read variable `uo`")),
        "{e}"
    );
}
