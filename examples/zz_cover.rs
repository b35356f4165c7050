use floebench::lcp::dump::LcpDump;
use floebench::lcp::lemke::{lemke, LemkeOptions};
fn main() {
    let dir = std::env::args().nth(1).unwrap();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().map_or(false, |e| e == "json"))
        .collect();
    files.sort();
    let variants: Vec<String> = std::env::args().skip(2).collect();
    let mut tot = vec![(0usize, 0usize, 0.0f64); variants.len()];
    for f in &files {
        let d = LcpDump::read(f).unwrap();
        let n = d.q.len();
        let m: Vec<f64> = d.m.iter().flatten().copied().collect();
        let q = &d.q;
        let qmax = q.iter().fold(0.0f64, |a, x| a.max(x.abs())).max(1e-300);
        let mut line = format!("{} n={}", f.file_name().unwrap().to_string_lossy(), n);
        for (vi, v) in variants.iter().enumerate() {
            let dm = (0..n)
                .fold(0.0f64, |a, i| a.max(m[i * n + i].abs()))
                .max(1e-300);
            let (kind, fl) = v
                .split_once(':')
                .map(|(a, b)| (a, b.parse::<f64>().unwrap()))
                .unwrap_or((v.as_str(), 1e-3));
            let cov: Option<Vec<f64>> = match kind {
                "ones" => None,
                "one_plus_absq" => Some(q.iter().map(|x| 1.0 + x.abs() / qmax).collect()),
                "infeasible" => Some(q.iter().map(|x| (-x).max(0.0) / qmax + 1e-3).collect()),
                "diag" => Some((0..n).map(|i| (m[i * n + i].abs() / dm).max(fl)).collect()),
                "sqrtdiag" => Some(
                    (0..n)
                        .map(|i| (m[i * n + i].abs() / dm).sqrt().max(fl))
                        .collect(),
                ),
                "diag2" => Some(
                    (0..n)
                        .map(|i| (m[i * n + i].abs() / dm).powi(2).max(fl))
                        .collect(),
                ),
                "rowsum" => Some(
                    (0..n)
                        .map(|i| {
                            let s: f64 = m[i * n..(i + 1) * n].iter().map(|x| x.abs()).sum();
                            s
                        })
                        .map(|s| s)
                        .collect::<Vec<_>>(),
                )
                .map(|v: Vec<f64>| {
                    let mx = v.iter().fold(0.0f64, |a, x| a.max(*x)).max(1e-300);
                    v.iter().map(|x| (x / mx).max(fl)).collect()
                }),
                "negq_only" => Some(
                    q.iter()
                        .map(|x| if *x < 0.0 { 1.0 } else { 1e-2 })
                        .collect(),
                ),
                _ => None,
            };
            let opts = LemkeOptions {
                covering: cov,
                ..LemkeOptions::default()
            };
            let t0 = std::time::Instant::now();
            let r = lemke(&m, q, &opts);
            let dt = t0.elapsed().as_secs_f64();
            let ok = r.residual <= 1e-10;
            tot[vi].0 += r.pivots;
            tot[vi].1 += ok as usize;
            tot[vi].2 += dt;
            line += &format!(" | {} {} {:.1e} {:.3}s", v, r.pivots, r.residual, dt);
        }
        println!("{line}");
    }
    for (vi, v) in variants.iter().enumerate() {
        println!(
            "TOTAL {} pivots {} solved {}/{} time {:.2}s",
            v,
            tot[vi].0,
            tot[vi].1,
            files.len(),
            tot[vi].2
        );
    }
}
