//! The parts of a problem file every storage shares: the header
//! (`d nc storage size0 size1`), then `W` (read by [`super::storage`]),
//! `q` and `mu`.

use super::tokens::Tokens;
use super::{storage, Fc2dError, Fc2dProblem};
use std::path::Path;

/// Parses the text of a problem file (see the module doc); `path` names the
/// file in errors.
pub fn parse_fc2d(text: &str, path: &Path) -> Result<Fc2dProblem, Fc2dError> {
    let mut tk = Tokens::new(text, path);
    tk.uint_eq(2, "the dimension d = 2")?;
    let (t, l) = tk.peek();
    let nc = tk.count(
        3,
        3,
        &[],
        "the number of contacts nc (2 nc reals of q and nc of mu follow)",
    )?;
    if nc == 0 {
        return Err(tk.error_at(t, l, "a number of contacts nc ≥ 1"));
    }
    let m = 2 * nc;
    let (t, l) = tk.next("the storage of W (0, 1 or 2)")?;
    let storage = match t {
        "0" => 0u8,
        "1" => 1,
        "2" => 2,
        _ => {
            return Err(tk.error_at(t, l, "an integer (storage: 0, 1 or 2)"));
        }
    };
    let rows = format!("size0 = 2 nc = {m}");
    tk.uint_eq(m, &rows)?;
    let cols = format!("size1 = 2 nc = {m}");
    tk.uint_eq(m, &cols)?;
    // What follows W: q and mu, 3 nc tokens at least.
    let tail = 3 * nc;
    let w = match storage {
        0 => storage::dense(&mut tk, nc, tail)?,
        1 => storage::sparse_block(&mut tk, nc, tail)?,
        _ => storage::csparse(&mut tk, nc, tail)?,
    };
    let q = tk.reals(m, "q, 2 nc of them")?;
    let mut mu = Vec::with_capacity(nc);
    for k in 0..nc {
        let (t, l) = tk.peek();
        let x = tk.real(&format!("a finite real (mu, {} of {nc})", k + 1))?;
        if x < 0.0 {
            return Err(tk.error_at(
                t,
                l,
                format!("a friction coefficient mu ≥ 0 ({} of {nc})", k + 1),
            ));
        }
        mu.push(x);
    }
    Ok(Fc2dProblem {
        contacts: nc,
        w,
        q,
        mu,
        storage,
    })
}
