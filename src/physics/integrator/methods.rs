//! The two methods' steps of the smooth integrator (module doc of
//! [`super`], docs/physics.md §4.1): explicit Euler and the adaptive
//! Dormand–Prince pair, each advancing one floe's state `y` over an
//! interval without a kink of the forcing.

use super::{IntegrationError, SmoothIntegrator, Wrench, N, Y};
use crate::model::Scenario;

impl SmoothIntegrator {
    pub(super) fn euler(
        &mut self,
        scn: &Scenario,
        i: usize,
        y: &mut Y,
        t0: f64,
        t1: f64,
        extra: &Wrench,
    ) -> Result<(), IntegrationError> {
        let hmax = self.max_step[i];
        let n = ((t1 - t0) / hmax).ceil().max(1.0);
        let h = (t1 - t0) / n;
        let mut t = t0;
        for _ in 0..n as u64 {
            let k = self.rhs(scn, i, t, y, extra);
            for (yj, kj) in y.iter_mut().zip(k.iter()) {
                *yj += h * kj;
            }
            t += h;
            self.stats.steps += 1;
        }
        if !y.iter().all(|v| v.is_finite()) {
            return Err(IntegrationError::NonFinite { floe: i, t });
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn dopri5(
        &mut self,
        scn: &Scenario,
        i: usize,
        y: &mut Y,
        t0: f64,
        t1: f64,
        extra: &Wrench,
        hint: &mut f64,
    ) -> Result<(), IntegrationError> {
        // Dormand–Prince 5(4) coefficients (Hairer, Nørsett & Wanner, table 5.2).
        const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
        const A: [[f64; 6]; 7] = [
            [0.0; 6],
            [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
            [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
            [
                19372.0 / 6561.0,
                -25360.0 / 2187.0,
                64448.0 / 6561.0,
                -212.0 / 729.0,
                0.0,
                0.0,
            ],
            [
                9017.0 / 3168.0,
                -355.0 / 33.0,
                46732.0 / 5247.0,
                49.0 / 176.0,
                -5103.0 / 18656.0,
                0.0,
            ],
            [
                35.0 / 384.0,
                0.0,
                500.0 / 1113.0,
                125.0 / 192.0,
                -2187.0 / 6784.0,
                11.0 / 84.0,
            ],
        ];
        const B: [f64; 7] = [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
            0.0,
        ];
        const E: [f64; 7] = [
            71.0 / 57600.0,
            0.0,
            -71.0 / 16695.0,
            71.0 / 1920.0,
            -17253.0 / 339200.0,
            22.0 / 525.0,
            -1.0 / 40.0,
        ];
        let (len, speed, energy) = self.scales[i];
        let rtol = self.rtol;
        let atol: Y = [
            rtol * len,
            rtol * len,
            rtol,
            rtol * speed,
            rtol * speed,
            rtol * speed / len,
            rtol * energy,
            rtol * energy,
            rtol * energy,
            rtol * energy,
        ];
        let span = t1 - t0;
        let hmax = self.max_step[i].min(span);
        let mut h = if *hint > 0.0 { hint.min(hmax) } else { hmax };
        let mut t = t0;
        let mut k = [[0.0; N]; 7];
        while t < t1 {
            let last = t + h >= t1 - 1e-15 * t1.abs().max(1.0);
            let hh = if last { t1 - t } else { h };
            k[0] = self.rhs(scn, i, t, y, extra);
            for s in 1..7 {
                let mut ys = *y;
                for (j, yj) in ys.iter_mut().enumerate() {
                    let mut acc = 0.0;
                    for (r, a) in A[s].iter().enumerate().take(s) {
                        acc += a * k[r][j];
                    }
                    *yj += hh * acc;
                }
                k[s] = self.rhs(scn, i, t + C[s] * hh, &ys, extra);
            }
            let mut ynew = *y;
            let mut err2 = 0.0;
            for j in 0..N {
                let mut acc = 0.0;
                let mut e = 0.0;
                for s in 0..7 {
                    acc += B[s] * k[s][j];
                    e += E[s] * k[s][j];
                }
                ynew[j] += hh * acc;
                let sc = atol[j] + rtol * y[j].abs().max(ynew[j].abs());
                let r = hh * e / sc;
                err2 += r * r;
            }
            let err = (err2 / N as f64).sqrt();
            if !err.is_finite() {
                return Err(IntegrationError::NonFinite { floe: i, t });
            }
            if err <= 1.0 {
                *y = ynew;
                t = if last { t1 } else { t + hh };
                self.stats.steps += 1;
                let grow = if err == 0.0 {
                    5.0
                } else {
                    (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
                };
                if !last || hh >= h {
                    h = (hh * grow).min(hmax);
                    *hint = h;
                }
            } else {
                self.stats.rejected += 1;
                h = hh * (0.9 * err.powf(-0.2)).clamp(0.1, 0.9);
                if h <= 1e-14 * t.abs().max(span) {
                    return Err(IntegrationError::StepUnderflow { floe: i, t });
                }
            }
        }
        Ok(())
    }
}
