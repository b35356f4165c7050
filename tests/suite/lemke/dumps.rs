//! LCP dumps: the bit-exact round trip, and the errors of malformed dumps and
//! of the strict reader, which name the key and the file.

use super::nonsym_pd;
use crate::common::tempdir;
use floebench::lcp::{solve, DumpError, Lcp, LcpDump, SolveOptions};
use floebench::rng::SplitMix64;

#[test]
fn dump_round_trip_is_bit_exact() {
    let tmp = tempdir();
    let dir = tmp.path();
    let mut rng = SplitMix64::new(0x5EED_F10E_0007);
    for k in 0..20 {
        let n = 1 + ((rng.next_u64() % 12) as usize);
        let mut m = nonsym_pd(&mut rng, n);
        // Awkward magnitudes: 17-significant-digit values, tiny, huge, subnormal.
        m[0] *= 1e-300;
        if n > 1 {
            m[1] = 5e-324;
            m[n] *= 1e250;
        }
        let q: Vec<f64> = (0..n)
            .map(|_| rng.range(-1.0, 1.0) * 10f64.powi((rng.next_u64() % 40) as i32 - 20))
            .collect();
        let lcp = Lcp::new(n, m, q).expect("sizes");
        let sol = solve(&lcp, &SolveOptions::default());
        // contacts consistent with n (n = 4m with friction, else n = m).
        let contacts = if n.is_multiple_of(4) && (k as usize).is_multiple_of(2) {
            n / 4
        } else {
            n
        };
        let dump = LcpDump::from_solution(&lcp, &sol, 12.5 + k as f64 / 3.0, contacts, None);
        let path = dir.join(format!("lcp_{k}.json"));
        dump.write(&path).expect("write");
        let back = LcpDump::read(&path).expect("read");
        assert_eq!(back, dump);
        for (a, b) in back.m.iter().flatten().zip(dump.m.iter().flatten()) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        let lcp_back = back.to_lcp().expect("square");
        assert_eq!(lcp_back, lcp);
        assert_eq!(back.status, sol.status.as_str());
    }
    // Non-finite values survive too.
    let dump = LcpDump {
        m: vec![vec![1.0, f64::INFINITY], vec![f64::NEG_INFINITY, 2.0]],
        q: vec![f64::NAN, -1.0],
        z: vec![0.0, 0.0],
        w: vec![f64::NAN, -1.0],
        t: 0.0,
        contacts: 2,
        friction_groups: None,
        pivots: 0,
        status: "Failed".into(),
    };
    let path = dir.join("nonfinite.json");
    dump.write(&path).expect("write");
    let back = LcpDump::read(&path).expect("read");
    assert!(
        back.q[0].is_nan() && back.m[0][1] == f64::INFINITY && back.m[1][0] == f64::NEG_INFINITY
    );
    // Atomic write leaves no temporary file behind.
    let names: Vec<String> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|s| !s.contains(".tmp")), "{names:?}");
    // The file has the documented keys.
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("lcp_3.json")).expect("read"))
            .expect("plain JSON");
    for key in ["M", "q", "z", "w", "t", "contacts", "pivots", "status"] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    assert!(v["M"][0].is_array() && v["contacts"].is_u64() && v["status"].is_string());
}

#[test]
fn malformed_dumps_give_errors_naming_the_problem() {
    let tmp = tempdir();
    let dir = tmp.path();
    let case = |name: &str, text: &str| -> DumpError {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        let e = LcpDump::read(&path).expect_err(name);
        let msg = e.to_string();
        assert!(msg.contains(name), "error does not name the file: {msg}");
        e
    };
    let tail = r#""q": [1, 2], "z": [0, 0], "w": [1, 2], "t": 0.5, "contacts": 2, "pivots": 0, "status": "Solved""#;
    let e = case("ragged.json", &format!(r#"{{"M": [[1, 0], [0]], {tail}}}"#));
    assert!(
        matches!(
            e,
            DumpError::RowLength {
                row: 1,
                len: 1,
                expected: 2,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("row 1 of M has 1 entries"), "{e}");
    let e = case(
        "nonsquare.json",
        &format!(r#"{{"M": [[1, 0, 0], [0, 1, 0]], {tail}}}"#),
    );
    assert!(
        matches!(
            e,
            DumpError::NotSquare {
                rows: 2,
                cols: 3,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("not square"), "{e}");
    let e = case(
        "shortq.json",
        r#"{"M": [[1, 0], [0, 1]], "q": [1], "z": [0, 0], "w": [1, 2], "t": 0, "contacts": 2, "pivots": 0, "status": "Solved"}"#,
    );
    assert!(e.to_string().contains("vector q has 1 entries"), "{e}");
    let e = case(
        "missing.json",
        r#"{"M": [[1]], "q": [1], "z": [0], "w": [1], "t": 0, "pivots": 0, "status": "x"}"#,
    );
    assert!(e.to_string().contains("missing field `contacts`"), "{e}");
    let e = case(
        "badnum.json",
        &format!(r#"{{"M": [[1, 0], [0, 1.2.3]], {tail}}}"#),
    );
    assert!(e.to_string().contains("invalid number \"1.2.3\""), "{e}");
    let e = case(
        "badcount.json",
        r#"{"M": [[1]], "q": [1], "z": [0], "w": [1], "t": 0, "contacts": -1, "pivots": 0, "status": "x"}"#,
    );
    assert!(e.to_string().contains("non-negative integer"), "{e}");
    let e = case("notjson.json", "this is not json");
    assert!(matches!(e, DumpError::Parse { .. }), "{e}");
    let missing = dir.join("does_not_exist.json");
    let e = LcpDump::read(&missing).expect_err("missing file");
    assert!(
        matches!(e, DumpError::Io { .. }) && e.to_string().contains("does_not_exist.json"),
        "{e}"
    );
    // Writing an inconsistent dump is refused before touching the disk.
    let bad = LcpDump {
        m: vec![vec![1.0, 2.0]],
        q: vec![1.0],
        z: vec![0.0],
        w: vec![1.0],
        t: 0.0,
        contacts: 0,
        friction_groups: None,
        pivots: 0,
        status: String::new(),
    };
    let e = bad
        .write(dir.join("bad_write.json"))
        .expect_err("not square");
    assert!(matches!(e, DumpError::NotSquare { .. }), "{e}");
    assert!(!dir.join("bad_write.json").exists());
}

#[test]
fn strict_dump_reader_names_the_key_and_the_file() {
    let tmp = tempdir();
    let dir = tmp.path();
    let read = |name: &str, text: &str| -> Result<LcpDump, String> {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        LcpDump::read(&path).map_err(|e| {
            let msg = e.to_string();
            assert!(msg.contains(name), "error does not name the file: {msg}");
            msg
        })
    };
    let ok = r#"{"t": 0.5, "contacts": 1, "pivots": 2, "status": "Solved", "M": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], "q": [-1, 0, 0, 0], "z": [1, 0, 0, 0], "w": [0, 0, 0, 0]}"#;
    assert!(read("ok.json", ok).is_ok());
    let bad = |name: &str, from: &str, to: &str, expect: &[&str]| {
        assert!(ok.contains(from), "{from}");
        let msg = read(name, &ok.replacen(from, to, 1)).expect_err(name);
        for e in expect {
            assert!(msg.contains(e), "{name}: {msg:?} lacks {e:?}");
        }
    };
    bad(
        "unknown.json",
        r#""t": 0.5"#,
        r#""t": 0.5, "extra": 1"#,
        &["unknown key \"extra\""],
    );
    bad(
        "dup.json",
        r#""t": 0.5"#,
        r#""t": 0.5, "t": 1"#,
        &["\"t\"", "more than once"],
    );
    bad(
        "missing.json",
        r#""pivots": 2, "#,
        "",
        &["missing field `pivots`"],
    );
    bad(
        "strnum_m.json",
        "[[1, 0",
        "[[\"1\", 0",
        &["key \"M\"", "number written as a string"],
    );
    bad(
        "strnum_q.json",
        r#""q": [-1"#,
        r#""q": ["-1""#,
        &["key \"q\"", "number written as a string"],
    );
    bad(
        "strnum_t.json",
        r#""t": 0.5"#,
        r#""t": "0.5""#,
        &["key \"t\"", "number written as a string"],
    );
    bad(
        "strcount.json",
        r#""contacts": 1"#,
        r#""contacts": "1""#,
        &["key \"contacts\"", "non-negative integer"],
    );
    bad(
        "fraction.json",
        r#""pivots": 2"#,
        r#""pivots": 2.5"#,
        &["key \"pivots\"", "non-negative integer"],
    );
    bad(
        "tagged.json",
        r#""t": 0.5"#,
        r#""t": "\u00010.5""#,
        &["key \"t\"", "number written as a string"],
    );
    bad(
        "contacts.json",
        r#""contacts": 1"#,
        r#""contacts": 3"#,
        &["\"contacts\" = 3", "n = 4"],
    );
    bad(
        "status.json",
        r#""status": "Solved""#,
        r#""status": "Done""#,
        &["\"status\" = \"Done\"", "not one of"],
    );
    bad(
        "solvednan.json",
        r#""q": [-1"#,
        r#""q": [NaN"#,
        &["\"status\" = \"Solved\"", "finite M and q"],
    );
    bad(
        "negz.json",
        r#""z": [1"#,
        r#""z": [-1"#,
        &["\"status\"", "z >= 0"],
    );
    bad(
        "type.json",
        r#""q": [-1, 0, 0, 0]"#,
        r#""q": {"a": 1}"#,
        &["key \"q\""],
    );
    // The documented strings for non-finite values, and bare tokens.
    let failed = ok.replace("\"Solved\"", "\"Failed\"");
    let d = read(
        "nan.json",
        &failed.replacen(
            "[-1, 0, 0, 0]",
            "[\"NaN\", \"Infinity\", \"-Infinity\", NaN]",
            1,
        ),
    )
    .expect("documented non-finite strings");
    assert!(
        d.q[0].is_nan()
            && d.q[1] == f64::INFINITY
            && d.q[2] == f64::NEG_INFINITY
            && d.q[3].is_nan()
    );
    // n = m (frictionless) is consistent too; n = 0 needs contacts = 0.
    let frictionless = r#"{"t": 0, "contacts": 2, "pivots": 0, "status": "Solved", "M": [[1, 0], [0, 1]], "q": [1, 1], "z": [0, 0], "w": [1, 1]}"#;
    assert!(read("frictionless.json", frictionless).is_ok());
    let empty = r#"{"t": 0, "contacts": 0, "pivots": 0, "status": "Solved", "M": [], "q": [], "z": [], "w": []}"#;
    assert!(read("empty.json", empty).is_ok());
}
