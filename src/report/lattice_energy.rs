//! The energy split of the impacts resolved in the floes' lattices
//! (`[fracture] impact = "lattice"`, docs/physics.md §9.10), one chart per
//! run whose lattices kept vibration: the kinetic energy of the rigid
//! motions, the vibration and dashpot energies the lattices took, the
//! energy dissipated (the rigid law's impacts and the lattices' integration
//! defect) and the fracture energy, against time, from `energy.csv`'s
//! columns. Drawn where people would rather look than read: how much of an
//! impact's energy went into the lattices.

use super::plot::{self, LineChart, Scale, Series};
use super::{plot_err, ReportError};
use crate::analysis::comparison::CaseComparison;
use crate::run::EnergySample;
use std::path::Path;

/// The curves of one chart: label and column.
type Column = (&'static str, fn(&EnergySample) -> f64);

/// The columns drawn, each in its palette colour.
const COLUMNS: [Column; 5] = [
    ("kinetic (rigid motions)", |e| e.kinetic),
    ("vibration", |e| e.ledger.vibration),
    ("dashpot", |e| e.ledger.dashpot),
    ("dissipated", |e| e.ledger.dissipated),
    ("fracture", |e| e.ledger.fracture),
];

/// `lattice_energy_<formulation>` for each run of `comp` whose `vibration`
/// is non-zero at some output (none otherwise); `add` records each figure
/// (file stem, alternative text, caption).
pub(super) fn figures(
    comp: &CaseComparison,
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    let name = &comp.scenario.name;
    for r in &comp.runs {
        if r.energy.iter().all(|e| e.ledger.vibration == 0.0) {
            continue;
        }
        let form = &r.summary.formulation;
        let series: Vec<Series> = COLUMNS
            .iter()
            .enumerate()
            .filter(|(_, (_, f))| r.energy.iter().any(|e| f(e) != 0.0))
            .map(|(k, (label, f))| {
                let points = r.energy.iter().map(|e| (e.t, f(e))).collect();
                Series {
                    dash: Some(0),
                    ..Series::new(*label, k, points)
                }
            })
            .collect();
        let file = format!("lattice_energy_{form}");
        let stem = dir.join(&file);
        plot::line_chart(
            &LineChart {
                title: &format!("{name}, {form}: where the impacts' energy went"),
                x_label: "t (s)",
                y_label: "energy (J)",
                series: &series,
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                marks: &[],
            },
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add(
            &file,
            format!("{form}: kinetic, vibration, dashpot and dissipated energy against time"),
            &format!(
                "{form}'s energy ledger at each output (energy.csv): the kinetic energy of the floes' rigid motions, the energy the lattices that resolved the impacts kept in vibration and took in their dashpots (impact = \"lattice\", docs/physics.md §9.10), the energy dissipated (the rigid law's impacts, the lattices' integration defect) and the fracture energy; the columns that stay zero are not drawn"
            ),
        );
    }
    Ok(())
}
