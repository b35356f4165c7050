//! The contact cache of the iterative solvers: each contact's last impulse,
//! as a mean force over its step, by contact identity ([`ContactKey`]:
//! bodies and vertex/edge features, stable while the same features touch).
//!
//! Entries of the current solve time and of the previous one are kept (a
//! contact absent for a whole step starts cold); a change of the number of
//! floes (a fracture: a broken floe keeps its index for one piece, the
//! other is appended, and the obstacles, numbered after the floes, move)
//! clears the cache, so no contact of a broken floe, nor any other, is
//! started from a stale impulse.

use super::problem::SparseContacts;
use crate::contact::ContactKey;
use std::collections::HashMap;

/// See the module doc.
#[derive(Debug, Clone, Default)]
pub struct ContactCache {
    t: f64,
    n_floes: usize,
    current: HashMap<ContactKey, [f64; 2]>,
    previous: HashMap<ContactKey, [f64; 2]>,
}

impl ContactCache {
    /// Starts a solve at time `t` (s) in a scene of `n_floes` floes.
    pub fn begin(&mut self, t: f64, n_floes: usize) {
        if n_floes != self.n_floes {
            self.current.clear();
            self.previous.clear();
            self.n_floes = n_floes;
        }
        if t != self.t {
            self.previous = std::mem::take(&mut self.current);
            self.t = t;
        }
    }

    /// The starting impulses of `prob` over a step of `h` (s): each cached
    /// contact's force times `h`, zero for the others; and how many were
    /// cached.
    pub fn start(&self, prob: &SparseContacts, h: f64) -> (Vec<[f64; 2]>, usize) {
        let mut hits = 0;
        let p = prob
            .keys
            .iter()
            .map(
                |k| match self.current.get(k).or_else(|| self.previous.get(k)) {
                    Some(f) => {
                        hits += 1;
                        [f[0] * h, f[1] * h]
                    }
                    None => [0.0, 0.0],
                },
            )
            .collect();
        (p, hits)
    }

    /// Stores the answer `p` of `prob` over a step of `h` (s) as forces.
    pub fn store(&mut self, prob: &SparseContacts, p: &[[f64; 2]], h: f64) {
        if !(h > 0.0 && h.is_finite()) {
            return;
        }
        for (k, pj) in prob.keys.iter().zip(p) {
            self.current.insert(*k, [pj[0] / h, pj[1] / h]);
        }
    }
}
