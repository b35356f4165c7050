//! The cohesive (crack-band) bond of the 2D lattice (docs/physics.md §7.3,
//! "The cohesive rule"; Bažant & Oh 1983): a bond elastic up to the
//! material's tensile strength, then softening linearly to zero force over
//! an opening that makes the whole force–opening curve hold `G h w`.
//!
//! **Law.** A bond of stiffness `κ` (N/m) opening a section `A = h w` (m²,
//! `w` its facet, as the toughness rule's) in a material of toughness `G`
//! (J/m²) and tensile strength `σ_t` (Pa) has the peak force `F_p = σ_t A`,
//! reached at the elastic opening `δ_e = F_p / κ`, and the envelope
//!
//! `F(δ) = κ δ` for `δ ≤ δ_e`, `F_p (δ_f − δ)/(δ_f − δ_e)` for
//! `δ_e < δ < δ_f`, `0` beyond;
//!
//! the area under it is the triangle `½ F_p δ_f` whatever `δ_e`, so
//! `½ F_p δ_f = G A` gives `δ_f = 2 G / σ_t` exactly: a material length,
//! the same at every spacing. The bond softens only when `δ_e < δ_f`
//! (`σ_t² A < 2 G κ`); otherwise the descending branch would have to turn
//! back (snap-back) and [`Cohesive::new`] gives `None`: such a bond, too
//! coarse for the band, falls back to the toughness rule (it breaks
//! elastically when it holds `G A`, the crack-band remedy of a reduced
//! strength, Bažant & Oh 1983), so every bond still costs `G A`.
//!
//! **Unloading** is secant, to the origin (a scalar damage): with `δ_m` the
//! largest opening reached, the bond pulls with `κ_s δ`, `κ_s = F(δ_m)/δ_m`
//! (`κ` while `δ_m ≤ δ_e`), for `0 < δ ≤ δ_m`, and follows the envelope
//! past `δ_m`. Compression is unaffected (`κ δ` for `δ ≤ 0`: the crack
//! closes). The dashpot in parallel is damaged with the spring, `c κ_s/κ`
//! in tension and `c` in compression, so a bond that has softened to
//! nothing carries no force when it breaks.
//!
//! **Energy.** The bond holds `½ κ_s δ²` (`½ κ δ²` in compression), and the
//! softening has dissipated `D = ½ (F_p δ_m − F(δ_m) δ_e)` (the area
//! between the envelope and the secant), `G A` at `δ_m = δ_f`, where the
//! bond breaks: that is its fracture energy, booked as it accrues. Work,
//! held energy and `D` balance exactly along the envelope:
//! `d(½ F δ + D)/dδ = F`.
//!
//! Reference: Z. P. Bažant and B. H. Oh (1983), Crack band theory for
//! fracture of concrete, *Matériaux et Constructions* 16, 155–177.

/// The softening state of one cohesive bond (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cohesive {
    /// The bond's stiffness `κ`, N/m.
    pub stiffness: f64,
    /// The elastic opening at the peak force, `δ_e = σ_t A / κ`, m.
    pub onset: f64,
    /// The opening at which it has softened to nothing and breaks,
    /// `δ_f = 2 G / σ_t`, m.
    pub fail: f64,
    /// The largest opening reached so far, `δ_m`, m (0 at first).
    pub reached: f64,
}

impl Cohesive {
    /// The cohesive bond of stiffness `stiffness` (N/m) opening `section`
    /// (m²) in a material of toughness `toughness` (J/m²) and tensile
    /// strength `strength` (Pa); `None` when it cannot soften (`δ_e ≥ δ_f`,
    /// snap-back: module doc).
    pub fn new(stiffness: f64, section: f64, toughness: f64, strength: f64) -> Option<Cohesive> {
        let onset = strength * section / stiffness;
        let fail = 2.0 * toughness / strength;
        (onset < fail).then_some(Cohesive {
            stiffness,
            onset,
            fail,
            reached: 0.0,
        })
    }

    /// The peak force `F_p = κ δ_e`, N.
    pub fn peak(&self) -> f64 {
        self.stiffness * self.onset
    }

    /// The envelope `F(δ)` at opening `d` ≥ 0 (m), N (module doc).
    pub fn envelope(&self, d: f64) -> f64 {
        if d <= self.onset {
            self.stiffness * d
        } else if d < self.fail {
            self.peak() * (self.fail - d) / (self.fail - self.onset)
        } else {
            0.0
        }
    }

    /// The secant stiffness `κ_s` (N/m) at opening `d` (m): `F(m)/m` for
    /// `m = max(δ_m, d)` past the onset, `κ` before.
    fn secant(&self, d: f64) -> f64 {
        let m = self.reached.max(d);
        if m <= self.onset {
            self.stiffness
        } else {
            self.envelope(m) / m
        }
    }

    /// Records the opening `d` (m): the largest one reached grows.
    pub fn open(&mut self, d: f64) {
        self.reached = self.reached.max(d);
    }

    /// Whether it has softened to nothing (`δ_m ≥ δ_f`): it breaks.
    pub fn failed(&self) -> bool {
        self.reached >= self.fail
    }

    /// The spring's tension (N, positive pulling) at opening `d` (m): `κ d`
    /// in compression, the secant's `κ_s d` in tension (the envelope past
    /// the largest opening reached).
    pub fn tension(&self, d: f64) -> f64 {
        if d <= 0.0 {
            self.stiffness * d
        } else {
            self.secant(d) * d
        }
    }

    /// The tension (N) of the spring and its dashpot `c` (N·s/m) at opening
    /// `d` (m) and rate `dv` (m/s): the dashpot damaged as the spring in
    /// tension (`c κ_s/κ`), whole in compression.
    pub fn force(&self, c: f64, d: f64, dv: f64) -> f64 {
        let damaged = if d > 0.0 {
            c * self.secant(d) / self.stiffness
        } else {
            c
        };
        self.tension(d) + damaged * dv
    }

    /// The power (W) its dashpot takes out at opening `d` and rate `dv`:
    /// the tension's power less the rate of the elastic energy it holds.
    pub fn dissipation(&self, c: f64, d: f64, dv: f64) -> f64 {
        (self.force(c, d, dv) - self.tension(d)) * dv
    }

    /// The elastic energy held at opening `d` (m), J: `½ κ_s d²` (`½ κ d²`
    /// in compression).
    pub fn energy(&self, d: f64) -> f64 {
        0.5 * self.tension(d) * d
    }

    /// The energy the softening has dissipated so far, J:
    /// `½ (F_p δ_m − F(δ_m) δ_e)` past the onset (module doc), `G A` once
    /// it has failed.
    pub fn dissipated(&self) -> f64 {
        let m = self.reached.min(self.fail);
        if m <= self.onset {
            0.0
        } else {
            0.5 * (self.peak() * m - self.envelope(m) * self.onset)
        }
    }

    /// The energy it takes to break it, the area under the envelope
    /// `½ F_p δ_f` (= `G A`), J.
    pub fn breaking_energy(&self) -> f64 {
        0.5 * self.peak() * self.fail
    }
}

impl super::BondRule {
    /// The softening state of a bond of stiffness `k` (N/m) opening
    /// `section` (m²): a [`Cohesive`] for a cohesive bond that can soften,
    /// `None` otherwise (every other rule is elastic until it breaks).
    pub fn cohesive(&self, k: f64, section: f64) -> Option<Cohesive> {
        match *self {
            super::BondRule::Cohesive {
                toughness,
                strength,
            } => Cohesive::new(k, section, toughness, strength),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The equilateral lattice's bond at spacing `s` (ν = 1/3, h = 1 m,
    /// E = 8.95 GPa): `κ = √3/2 E h`, `A = h s/√3`.
    fn bond(s: f64) -> Cohesive {
        let e = 8.95e9;
        Cohesive::new(3f64.sqrt() / 2.0 * e, s / 3f64.sqrt(), 2.5, 2.5e5).unwrap()
    }

    #[test]
    fn the_envelope_is_continuous_and_its_area_is_g_a() {
        let b = bond(0.25);
        let a = 0.25 / 3f64.sqrt();
        assert!((b.fail - 2.0 * 2.5 / 2.5e5).abs() < 1e-20);
        assert!((b.envelope(b.onset) - 2.5e5 * a).abs() < 1e-9 * 2.5e5 * a);
        assert!((b.breaking_energy() - 2.5 * a).abs() < 1e-12 * 2.5 * a);
        assert_eq!(b.envelope(b.fail), 0.0);
    }

    #[test]
    fn unloading_is_secant_and_compression_is_unaffected() {
        let mut b = bond(0.25);
        let mid = 0.5 * (b.onset + b.fail);
        b.open(mid);
        let f = b.envelope(mid);
        assert!((b.tension(0.5 * mid) - 0.5 * f).abs() < 1e-9 * f);
        assert_eq!(b.tension(-1e-6), -b.stiffness * 1e-6);
        // Reloading past the largest opening follows the envelope.
        let further = 0.5 * (mid + b.fail);
        assert_eq!(b.tension(further), b.envelope(further));
        // The dissipated energy plus the energy held is the work on the
        // envelope so far.
        let work = 0.5 * b.peak() * b.onset + 0.5 * (b.peak() + f) * (mid - b.onset);
        assert!((b.dissipated() + b.energy(mid) - work).abs() < 1e-12 * work);
    }

    #[test]
    fn a_bond_too_coarse_for_the_band_does_not_soften() {
        // s > 2 E G / ((1 − ν) σ_t²) = 3 E G / σ_t² at ν = 1/3: 1.07 m here.
        let e = 8.95e9;
        let at = |s: f64| Cohesive::new(3f64.sqrt() / 2.0 * e, s / 3f64.sqrt(), 2.5, 2.5e5);
        assert!(at(1.0).is_some());
        assert!(at(1.1).is_none());
    }
}
