//! A pantograph's frequency response at the head, and a lumped model fitted to a measured one
//! (issue 43, item 3: `pcsim pantograph frf` and `pcsim pantograph fit`).
//!
//! The response is the receptance `X₀/F₀` (m/N) of [`Lumped::receptance`], or the apparent mass
//! `F₀/A₀ = −1/(ω² X₀/F₀)` (kg) that pantograph test rigs commonly report. A measured response
//! is read from CSV text with the units in its header (`frequency_hz`, `magnitude_m_per_n` or
//! `magnitude_kg`, `phase_deg`); the fit is a least-squares fit of the chain's masses, springs
//! and dampers to it: bounded Levenberg–Marquardt on the logarithms of the parameters (bounded
//! to a factor of [`BOUND_FACTOR`] around the starting pantograph, the case's) from several
//! starts inside the bounds, the residual the complex relative misfit at every frequency, and
//! each parameter's standard uncertainty from the Jacobian at the optimum (`s² (JᵀJ)⁻¹`, `s²`
//! the residual variance). A residual above [`FitSpec::max_residual_rms`] is a failure
//! ([`Fit::check`]), never a block to paste.

use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};

use crate::error::CaseError;
use crate::input::bounds::inv;
use crate::model::pantograph::{Lumped, Strip};

/// The fit's bounds: each parameter within this factor of the starting pantograph's value.
pub const BOUND_FACTOR: f64 = 4.0;

/// What a response gives at each frequency.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Quantity {
    /// Displacement over force at the head, m/N.
    Receptance,
    /// Force over acceleration at the head, kg.
    ApparentMass,
}

impl Quantity {
    /// Its magnitude column in a CSV header (the unit in the name).
    pub fn column(self) -> &'static str {
        match self {
            Quantity::Receptance => "magnitude_m_per_n",
            Quantity::ApparentMass => "magnitude_kg",
        }
    }

    /// The response of `p` at `f_hz` as this quantity.
    pub fn of(self, p: &Lumped, f_hz: f64) -> Option<Complex<f64>> {
        let w = 2.0 * std::f64::consts::PI * f_hz;
        let h = p.receptance(w)?;
        Some(match self {
            Quantity::Receptance => h,
            Quantity::ApparentMass => -(h * w * w).inv(),
        })
    }
}

/// A response: frequencies and complex values.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// What it gives.
    pub quantity: Quantity,
    /// Frequencies, Hz, increasing.
    pub frequency_hz: Vec<f64>,
    /// The complex response at each.
    pub value: Vec<Complex<f64>>,
    /// Where it came from (a file's name, or `model`).
    pub source: String,
}

impl Response {
    /// The model's response at `frequency_hz`. An error names the frequency where the chain's
    /// dynamic stiffness is singular.
    pub fn of_model(
        p: &Lumped,
        quantity: Quantity,
        frequency_hz: &[f64],
    ) -> Result<Self, CaseError> {
        let value = frequency_hz
            .iter()
            .map(|&f| {
                quantity.of(p, f).ok_or_else(|| {
                    inv(
                        "frequency_hz",
                        f,
                        "the chain's dynamic stiffness is singular there",
                    )
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            quantity,
            frequency_hz: frequency_hz.to_vec(),
            value,
            source: "model".into(),
        })
    }

    /// `n` frequencies from `from_hz` to `to_hz`, evenly spaced on a logarithmic scale.
    pub fn log_grid(from_hz: f64, to_hz: f64, n: usize) -> Result<Vec<f64>, CaseError> {
        if !(from_hz.is_finite() && from_hz > 0.0) {
            return Err(inv("from_hz", from_hz, "a positive frequency"));
        }
        if !(to_hz.is_finite() && to_hz > from_hz) {
            return Err(inv("to_hz", to_hz, "a frequency above from_hz"));
        }
        if !(2..=100_000).contains(&n) {
            return Err(inv("points", n, "between 2 and 100000"));
        }
        let (a, b) = (from_hz.ln(), to_hz.ln());
        Ok((0..n)
            .map(|i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
            .collect())
    }

    /// The frequencies of its resonances, Hz: the local maxima of the magnitude that stand out
    /// from the lower of their two sides (the lowest magnitude between the peak and the nearest
    /// higher point, or the range's end) by at least 1 % of their height. Rounding noise on a
    /// flat response (a relative 1e-15) is no peak.
    pub fn peaks(&self) -> Vec<f64> {
        let m: Vec<f64> = self.value.iter().map(|h| h.norm()).collect();
        let n = m.len();
        let side = |i: usize, step: isize| {
            let mut lowest = m[i];
            let mut j = i as isize + step;
            while j >= 0 && (j as usize) < n && m[j as usize] <= m[i] {
                lowest = lowest.min(m[j as usize]);
                j += step;
            }
            lowest
        };
        (1..n.saturating_sub(1))
            .filter(|&i| m[i] > m[i - 1] && m[i] >= m[i + 1])
            .filter(|&i| m[i] - side(i, -1).max(side(i, 1)) >= 0.01 * m[i])
            .map(|i| self.frequency_hz[i])
            .collect()
    }

    /// As CSV text: `frequency_hz`, the magnitude with its unit, `phase_deg`.
    pub fn to_csv(&self) -> String {
        let mut s = format!("frequency_hz,{},phase_deg\n", self.quantity.column());
        for (f, h) in self.frequency_hz.iter().zip(&self.value) {
            s.push_str(&format!(
                "{f:.6},{:.9e},{:.4}\n",
                h.norm(),
                h.arg().to_degrees()
            ));
        }
        s
    }

    /// A measured response from CSV text (`source` names it in errors): a header naming
    /// `frequency_hz`, `magnitude_m_per_n` or `magnitude_kg`, and `phase_deg`, then one row per
    /// frequency, increasing. Each malformed line or value is refused by its line and column.
    pub fn from_csv(text: &str, source: &str) -> Result<Self, CaseError> {
        let text = crate::input::without_bom(text);
        let bad = |line: usize, what: &str, reason: &str| CaseError::Invalid {
            field: format!("{source}: line {line}"),
            value: what.to_string(),
            reason: reason.to_string(),
        };
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (_, header) = lines
            .next()
            .ok_or_else(|| bad(1, "", "empty: give a header (frequency_hz, magnitude_m_per_n or magnitude_kg, phase_deg) and rows"))?;
        let cols: Vec<&str> = header.split(',').map(str::trim).collect();
        let find = |name: &str| cols.iter().position(|c| *c == name);
        let quantity = match (find("magnitude_m_per_n"), find("magnitude_kg")) {
            (Some(_), None) => Quantity::Receptance,
            (None, Some(_)) => Quantity::ApparentMass,
            _ => {
                return Err(bad(
                    1,
                    header,
                    "the header names the magnitude with its unit: magnitude_m_per_n (receptance) or magnitude_kg (apparent mass), one of them",
                ))
            }
        };
        let (Some(fi), Some(mi), Some(pi)) = (
            find("frequency_hz"),
            find(quantity.column()),
            find("phase_deg"),
        ) else {
            return Err(bad(
                1,
                header,
                "the header needs frequency_hz and phase_deg (units in the names)",
            ));
        };
        let mut frequency_hz: Vec<f64> = Vec::new();
        let mut value = Vec::new();
        for (k, line) in lines {
            let n = k + 1;
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != cols.len() {
                return Err(bad(
                    n,
                    line,
                    &format!("{} values where the header has {}", cells.len(), cols.len()),
                ));
            }
            let num = |i: usize, name: &str| -> Result<f64, CaseError> {
                let x: f64 = cells[i]
                    .parse()
                    .map_err(|_| bad(n, cells[i], &format!("{name} is not a number")))?;
                if !x.is_finite() {
                    return Err(bad(n, cells[i], &format!("{name} is not finite")));
                }
                Ok(x)
            };
            let (f, m, p) = (
                num(fi, "frequency_hz")?,
                num(mi, quantity.column())?,
                num(pi, "phase_deg")?,
            );
            if f <= 0.0 {
                return Err(bad(n, cells[fi], "frequency_hz must be positive"));
            }
            if frequency_hz.last().is_some_and(|&last| f <= last) {
                return Err(bad(
                    n,
                    cells[fi],
                    "frequencies must increase from row to row",
                ));
            }
            if m <= 0.0 {
                return Err(bad(n, cells[mi], "a magnitude is positive"));
            }
            frequency_hz.push(f);
            value.push(Complex::from_polar(m, p.to_radians()));
        }
        if frequency_hz.len() < 4 {
            return Err(bad(
                1,
                header,
                &format!("{} rows: a response needs at least 4", frequency_hz.len()),
            ));
        }
        Ok(Self {
            quantity,
            frequency_hz,
            value,
            source: source.to_string(),
        })
    }
}

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Fitted {
    /// Its name in the case (`masses_kg[0]`, `stiffness_n_per_m[1]`, `damping_ns_per_m[0]`).
    pub name: String,
    /// The starting value (the case's).
    pub start: f64,
    /// The fitted value.
    pub value: f64,
    /// Its standard uncertainty (one standard deviation).
    pub std: f64,
    /// Whether the fit ended at a bound (then the uncertainty does not describe it).
    pub at_bound: bool,
}

/// A fit's answer: the fitted pantograph and its record.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The fitted pantograph (its uplift and aerodynamic force the starting one's).
    pub pantograph: Lumped,
    /// What `fit.json` holds (written and read back through this type).
    pub record: FitRecord,
}

/// A fit as `fit.json` holds it (`pcsim schema fit`): each fitted value with its uncertainty,
/// the residual, the settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FitRecord {
    /// Each parameter.
    pub parameters: Vec<Fitted>,
    /// RMS of the relative complex misfit over the frequencies.
    pub residual_rms: f64,
    /// The same at the start.
    pub start_residual_rms: f64,
    /// Evaluations of the residuals.
    pub evaluations: u64,
    /// The measurement's source.
    pub source: String,
    /// The settings.
    pub spec: FitSpec,
    /// Whether the residual is within `spec.max_residual_rms` (else the fit is a failure: no
    /// case block is handed over).
    pub converged: bool,
}

impl Fit {
    /// An error when the fit is not one a user may paste (its residual above
    /// `spec.max_residual_rms`): the residual, the parameters left at a bound, and, when the
    /// measurement fits well read as the other quantity (an apparent mass under a receptance
    /// header, or the reverse: a common slip), that.
    pub fn check(&self, start: &Lumped, measured: &Response) -> Result<(), CaseError> {
        if self.record.converged {
            return Ok(());
        }
        let at_bound: Vec<&str> = (self.record.parameters.iter())
            .filter(|p| p.at_bound)
            .map(|p| p.name.as_str())
            .collect();
        let other = match measured.quantity {
            Quantity::Receptance => Quantity::ApparentMass,
            Quantity::ApparentMass => Quantity::Receptance,
        };
        let swapped = Response {
            quantity: other,
            ..measured.clone()
        };
        let quick = FitSpec {
            starts: 2,
            ..self.record.spec
        };
        let hint = match fit_with(start, &swapped, &quick, &mut |_, _| {}) {
            Ok(f) if f.record.converged => format!(
                "; read as {} ({}) it fits at {:.2} % RMS: is the header's unit right?",
                match other {
                    Quantity::Receptance => "a receptance",
                    Quantity::ApparentMass => "an apparent mass",
                },
                other.column(),
                100.0 * f.record.residual_rms
            ),
            _ => String::new(),
        };
        Err(inv(
            &format!("{}: fit", self.record.source),
            format!("residual {:.2} % RMS", 100.0 * self.record.residual_rms),
            &format!(
                "above the {:.1} % accepted (fit.max_residual_rms): the chain does not describe this measurement{}{}; no case block is written",
                100.0 * self.record.spec.max_residual_rms,
                if at_bound.is_empty() {
                    String::new()
                } else {
                    format!(", and {} ended at a bound of the start's factor of {BOUND_FACTOR}", at_bound.join(", "))
                },
                hint
            ),
        ))
    }

    /// The fitted pantograph as a case's `[[pantographs]]` block named `name`, each fitted value
    /// with the measurement (`label`) as its source; the uplift and the aerodynamic force are the
    /// starting case's (a frequency response does not measure them).
    pub fn case_block(&self, name: &str, label: &str) -> String {
        let source = format!(
            "fitted by pcsim pantograph fit to {label} (residual {:.2} % RMS; uncertainties in fit.json)",
            100.0 * self.record.residual_rms
        )
        .replace('"', "'");
        let list = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.6e}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let p = &self.pantograph;
        let name = name.replace('"', "'");
        format!(
            "# The pantograph `{name}` fitted to {label}; paste into a case. Its uplift and aerodynamic\n\
             # force are the case's: a frequency response does not measure them.\n\
             [[pantographs]]\nkind = \"lumped\"\nname = \"{name}\"\n\
             masses_kg = {{ value = [{}], source = \"{source}\" }}\n\
             stiffness_n_per_m = {{ value = [{}], source = \"{source}\" }}\n\
             damping_ns_per_m = {{ value = [{}], source = \"{source}\" }}\n\
             uplift_n = {:?}\n{}aero_coeffs_kmh = [{}]\n",
            list(&p.masses_kg),
            list(&p.stiffness_n_per_m),
            list(&p.damping_ns_per_m),
            p.uplift_n,
            p.uplift_by_height.as_ref().map_or(String::new(), |t| {
                let l = |v: &[f64]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ");
                format!(
                    "uplift_by_height = {{ height_m = [{}], uplift_n = [{}] }}\n",
                    l(&t.height_m),
                    l(&t.uplift_n)
                )
            }),
            p.aero_coeffs_kmh
                .iter()
                .map(|x| format!("{x:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        ) + &strip_blocks(p, &source)
    }
}

/// The fitted head's strips as `[[pantographs.strips]]` blocks: the fitted design for every
/// strip, its place, face and contact stiffness the case's.
fn strip_blocks(p: &Lumped, source: &str) -> String {
    p.strips
        .iter()
        .map(|s| {
            format!(
                "\n[[pantographs.strips]]\n\
                 mass_kg = {{ value = {:.6e}, source = \"{source}\" }}\n\
                 stiffness_n_per_m = {{ value = {:.6e}, source = \"{source}\" }}\n\
                 damping_ns_per_m = {{ value = {:.6e}, source = \"{source}\" }}\n\
                 along_m = {:?}\nheight_offset_m = {:?}\ncontact_stiffness_n_per_m = {:?}\n",
                s.mass_kg,
                s.stiffness_n_per_m,
                s.damping_ns_per_m,
                s.along_m,
                s.height_offset_m,
                s.contact_stiffness_n_per_m
            )
        })
        .collect()
}

/// Whether two strips have the same mass, spring and damper (the fit's one strip design).
fn same_strip(a: &Strip, b: &Strip) -> bool {
    (a.mass_kg, a.stiffness_n_per_m, a.damping_ns_per_m)
        == (b.mass_kg, b.stiffness_n_per_m, b.damping_ns_per_m)
}

/// The chain's parameters in a fixed order: masses, stiffnesses, dampings; then, with strips,
/// the one strip design's mass, stiffness and damping (every strip alike).
fn params(p: &Lumped) -> Vec<f64> {
    let strip = p
        .strips
        .first()
        .map(|s| [s.mass_kg, s.stiffness_n_per_m, s.damping_ns_per_m]);
    p.masses_kg
        .iter()
        .chain(&p.stiffness_n_per_m)
        .chain(&p.damping_ns_per_m)
        .chain(strip.iter().flatten())
        .copied()
        .collect()
}

fn names(p: &Lumped) -> Vec<String> {
    let n = p.masses_kg.len();
    let mut v = Vec::new();
    for what in ["masses_kg", "stiffness_n_per_m", "damping_ns_per_m"] {
        v.extend((0..n).map(|i| format!("{what}[{i}]")));
    }
    if !p.strips.is_empty() {
        for what in ["mass_kg", "stiffness_n_per_m", "damping_ns_per_m"] {
            v.push(format!("strips[*].{what}"));
        }
    }
    v
}

fn with_params(p: &Lumped, x: &[f64]) -> Lumped {
    let n = p.masses_kg.len();
    Lumped {
        masses_kg: x[..n].to_vec(),
        stiffness_n_per_m: x[n..2 * n].to_vec(),
        damping_ns_per_m: x[2 * n..3 * n].to_vec(),
        strips: (p.strips.iter())
            .map(|s| Strip {
                mass_kg: x[3 * n],
                stiffness_n_per_m: x[3 * n + 1],
                damping_ns_per_m: x[3 * n + 2],
                ..s.clone()
            })
            .collect(),
        ..p.clone()
    }
}

/// The misfit's residuals of `p` against `m`: per frequency, the real and imaginary parts of
/// `(model − measured)/|measured|` (a singular point counts as a misfit of 1e3).
fn residuals(p: &Lumped, m: &Response) -> Vec<f64> {
    let mut r = Vec::with_capacity(2 * m.value.len());
    for (&f, &h) in m.frequency_hz.iter().zip(&m.value) {
        let d = match m.quantity.of(p, f) {
            Some(x) => (x - h) / h.norm(),
            None => Complex::new(1e3, 1e3),
        };
        r.extend([d.re, d.im]);
    }
    r
}

/// The fit's settings (`Default`: 8 starts, seed 1, a residual of at most 10 % RMS).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FitSpec {
    /// Starts of the least-squares method: the case's values, then `starts − 1` points drawn
    /// uniformly (on the logarithms) inside the bounds; the best end is the answer.
    pub starts: usize,
    /// The draws' seed.
    pub seed: u64,
    /// The largest RMS relative misfit accepted (0.10: 10 %); above it the fit is a failure.
    pub max_residual_rms: f64,
}

impl Default for FitSpec {
    fn default() -> Self {
        Self {
            starts: 8,
            seed: 1,
            max_residual_rms: 0.10,
        }
    }
}

impl FitSpec {
    /// Refuse settings the fit cannot honour, by their field.
    pub fn check(&self) -> Result<(), CaseError> {
        if !(1..=MAX_STARTS).contains(&self.starts) {
            return Err(inv(
                "fit.starts",
                self.starts,
                &format!("from 1 to {MAX_STARTS}"),
            ));
        }
        if !(self.max_residual_rms.is_finite() && self.max_residual_rms > 0.0) {
            return Err(inv(
                "fit.max_residual_rms",
                self.max_residual_rms,
                "a positive fraction (0.10: 10 % RMS)",
            ));
        }
        Ok(())
    }
}

/// The most starts a fit takes.
pub const MAX_STARTS: usize = 64;

/// The most frequencies a measured response may hold (each start costs about
/// `60 × 2 × parameters` evaluations of the chain at every frequency): thin a longer record.
pub const MAX_FREQUENCIES: usize = 20_000;

/// The residuals on the logarithms `u` of the parameters, clamped into the bounds.
struct Problem<'a> {
    start: &'a Lumped,
    measured: &'a Response,
    /// Natural logarithms of the bounds.
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Residual evaluations so far.
    count: u64,
}

impl Problem<'_> {
    fn x_of(&self, u: &[f64]) -> Vec<f64> {
        (u.iter().zip(self.lo.iter().zip(&self.hi)))
            .map(|(&v, (&l, &h))| v.clamp(l, h).exp())
            .collect()
    }

    fn residuals(&mut self, u: &[f64]) -> Vec<f64> {
        self.count += 1;
        residuals(&with_params(self.start, &self.x_of(u)), self.measured)
    }

    /// The Jacobian of the residuals in `u` by central differences (one-sided at a bound).
    fn jacobian(&mut self, u: &[f64]) -> Vec<Vec<f64>> {
        let h = 1e-6;
        let np = u.len();
        let mut cols = Vec::with_capacity(np);
        for j in 0..np {
            let (mut up, mut dn) = (u.to_vec(), u.to_vec());
            up[j] = (u[j] + h).min(self.hi[j]);
            dn[j] = (u[j] - h).max(self.lo[j]);
            let (ru, rd) = (self.residuals(&up), self.residuals(&dn));
            let d = up[j] - dn[j];
            cols.push(ru.iter().zip(&rd).map(|(a, b)| (a - b) / d).collect());
        }
        cols
    }
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Levenberg–Marquardt from `u0`, each step projected into the bounds (Marquardt's scaling by
/// the diagonal of `JᵀJ`; `λ` divided by 3 on a step that lowers the cost, multiplied by 4 on
/// one that does not). Ends when a step lowers the cost by less than 1e-12 of it, when `λ`
/// exceeds 1e12 (no direction lowers it), or after 200 iterations. Returns the end and its cost.
///
/// Written here rather than taken from a crate: argmin offers Gauss–Newton without bounds, and
/// the `levenberg-marquardt` crate has no bounds either and brings nalgebra, a second linear
/// algebra library, for a system of at most a dozen unknowns.
fn levenberg_marquardt(p: &mut Problem<'_>, u0: &[f64]) -> (Vec<f64>, f64) {
    let np = u0.len();
    let mut u: Vec<f64> = (u0.iter().zip(p.lo.iter().zip(&p.hi)))
        .map(|(&v, (&l, &h))| v.clamp(l, h))
        .collect();
    let mut r = p.residuals(&u);
    let mut cost = sum_sq(&r);
    let mut lambda = 1e-3;
    for _ in 0..200 {
        let jac = p.jacobian(&u);
        let mut jtj = vec![0.0; np * np];
        let mut g = vec![0.0; np];
        for a in 0..np {
            g[a] = crate::linalg::dot(&jac[a], &r);
            for b in a..np {
                let v = crate::linalg::dot(&jac[a], &jac[b]);
                jtj[a * np + b] = v;
                jtj[b * np + a] = v;
            }
        }
        let mut moved = false;
        while lambda <= 1e12 {
            let mut m = jtj.clone();
            for a in 0..np {
                m[a * np + a] += lambda * jtj[a * np + a].max(1e-12);
            }
            let Some(inv_m) = crate::linalg::invert_small(&m, np) else {
                lambda *= 4.0;
                continue;
            };
            let step = crate::linalg::mat_vec(&inv_m, np, &g);
            let trial: Vec<f64> = (0..np)
                .map(|a| (u[a] - step[a]).clamp(p.lo[a], p.hi[a]))
                .collect();
            let rt = p.residuals(&trial);
            let ct = sum_sq(&rt);
            if ct < cost {
                let gain = cost - ct;
                u = trial;
                r = rt;
                cost = ct;
                lambda = (lambda / 3.0).max(1e-12);
                moved = gain > 1e-12 * cost.max(1e-300);
                break;
            }
            lambda *= 4.0;
        }
        if !moved {
            break;
        }
    }
    (u, cost)
}

/// `JᵀJ` of the residuals at the parameters `x` (`n_res` residuals; `J` in the logarithms of the
/// parameters, by central differences), row-major: the fit's covariance is its inverse.
fn normal_matrix(start: &Lumped, x: &[f64], measured: &Response, n_res: usize) -> Vec<f64> {
    let np = x.len();
    let h: f64 = 1e-6;
    let mut jac = vec![vec![0.0; np]; n_res];
    for j in 0..np {
        let mut up = x.to_vec();
        let mut dn = x.to_vec();
        up[j] *= h.exp();
        dn[j] *= (-h).exp();
        let (ru, rd) = (
            residuals(&with_params(start, &up), measured),
            residuals(&with_params(start, &dn), measured),
        );
        for i in 0..n_res {
            jac[i][j] = (ru[i] - rd[i]) / (2.0 * h);
        }
    }
    let mut jtj = vec![0.0; np * np];
    for row in &jac {
        for a in 0..np {
            for b in 0..np {
                jtj[a * np + b] += row[a] * row[b];
            }
        }
    }
    jtj
}

/// Fit the chain of `start` with the default settings ([`fit_with`]).
pub fn fit(start: &Lumped, measured: &Response) -> Result<Fit, CaseError> {
    fit_with(start, measured, &FitSpec::default(), &mut |_, _| {})
}

/// The fit's starting values (the chain's parameters), refusing a start or a measurement the
/// fit cannot take: strips unlike each other, a value not positive, too few or too many
/// frequencies.
fn fit_start(start: &Lumped, measured: &Response) -> Result<Vec<f64>, CaseError> {
    let x0 = params(start);
    let np = x0.len();
    if let Some(s) = start
        .strips
        .iter()
        .position(|s| !same_strip(s, &start.strips[0]))
    {
        return Err(inv(
            &format!("pantographs.strips[{s}]"),
            "a strip unlike the first",
            "the fit takes a head's strips alike (one mass, spring and damper for all): the response at the head, a force shared by the strips, cannot tell unequal strips apart",
        ));
    }
    if let Some(i) = x0.iter().position(|&v| !(v.is_finite() && v > 0.0)) {
        return Err(inv(
            &format!("pantographs.{}", names(start)[i]),
            x0[i],
            "the fit starts from positive values (a zero spring or damper has no scale to fit)",
        ));
    }
    if measured.value.len() * 2 < 2 * np {
        return Err(inv(
            "measured",
            measured.value.len(),
            &format!("{np} parameters need at least {np} frequencies"),
        ));
    }
    if measured.value.len() > MAX_FREQUENCIES {
        return Err(inv(
            "measured",
            format!("{} frequencies", measured.value.len()),
            &format!("at most {MAX_FREQUENCIES} (each start evaluates the chain about 60 × 2 × {np} times at every frequency): thin the record, a chain of {np} parameters needs a few hundred"),
        ));
    }
    Ok(x0)
}

/// Fit the chain of `start` (its number of masses, its values as the first start and the centre
/// of the bounds) to `measured`: bounded Levenberg–Marquardt on the logarithms of the
/// parameters from `spec.starts` starts (the case's values, then seeded draws inside the
/// bounds), the best end taken. `progress(k, n)` is called as start `k` of `n` ends. The
/// answer's [`FitRecord::converged`] says whether its residual is within `spec.max_residual_rms`;
/// [`Fit::check`] turns a fit that is not into an error.
pub fn fit_with(
    start: &Lumped,
    measured: &Response,
    spec: &FitSpec,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Fit, CaseError> {
    spec.check()?;
    let x0 = fit_start(start, measured)?;
    let np = x0.len();
    let mut problem = Problem {
        start,
        measured,
        lo: x0.iter().map(|v| (v / BOUND_FACTOR).ln()).collect(),
        hi: x0.iter().map(|v| (v * BOUND_FACTOR).ln()).collect(),
        count: 0,
    };
    let u0: Vec<f64> = x0.iter().map(|v| v.ln()).collect();
    let start_cost = sum_sq(&problem.residuals(&u0));
    let mut rng = crate::model::wind_field::SplitMix64::new(spec.seed);
    let mut best: Option<(Vec<f64>, f64)> = None;
    for k in 0..spec.starts {
        let from: Vec<f64> = if k == 0 {
            u0.clone()
        } else {
            (problem.lo.iter().zip(&problem.hi))
                .map(|(&l, &h)| l + (h - l) * rng.uniform())
                .collect()
        };
        let (u, c) = levenberg_marquardt(&mut problem, &from);
        if best.as_ref().is_none_or(|(_, b)| c < *b) {
            best = Some((u, c));
        }
        progress(k + 1, spec.starts);
    }
    let (u, _) = best.expect("at least one start");
    let x: Vec<f64> = u
        .iter()
        .zip(problem.lo.iter().zip(&problem.hi))
        .map(|(&v, (&l, &h))| v.clamp(l, h).exp())
        .collect();
    let fitted = with_params(start, &x);
    let r = residuals(&fitted, measured);
    let dof = (r.len() as f64 - np as f64).max(1.0);
    let s2 = r.iter().map(|v| v * v).sum::<f64>() / dof;
    let jtj = normal_matrix(start, &x, measured, r.len());
    let cov = crate::linalg::invert_small(&jtj, np);
    let names = names(start);
    let parameters = (0..np)
        .map(|j| {
            let var = cov.as_ref().map_or(f64::INFINITY, |c| c[j * np + j] * s2);
            let at_bound =
                (u[j] - problem.lo[j]).abs() < 1e-6 || (u[j] - problem.hi[j]).abs() < 1e-6;
            Fitted {
                name: names[j].clone(),
                start: x0[j],
                value: x[j],
                std: x[j] * var.max(0.0).sqrt(),
                at_bound,
            }
        })
        .collect();
    let rms = |c: f64| (c / measured.value.len() as f64).sqrt();
    let residual_rms = rms(sum_sq(&r));
    Ok(Fit {
        pantograph: fitted,
        record: FitRecord {
            parameters,
            residual_rms,
            start_residual_rms: rms(start_cost),
            evaluations: problem.count,
            source: measured.source.clone(),
            spec: *spec,
            converged: residual_rms <= spec.max_residual_rms,
        },
    })
}

/// `pcsim pantograph frf` as a study of the contract (issue 52): a pantograph's response at
/// the head over a grid of frequencies, written as `frf.csv` and `frf.json`, with its answer
/// (the chain and its resonances) and its figures (magnitude and phase) declared as data.
#[derive(Debug, Clone, PartialEq)]
pub struct FrfStudy {
    /// The pantograph's name (as the case names it).
    pub name: String,
    /// Its chain.
    pub pantograph: Lumped,
    /// What the response gives.
    pub quantity: Quantity,
    /// The frequencies, Hz ([`Response::log_grid`]).
    pub frequency_hz: Vec<f64>,
}

/// What a response study gives (`frf.json`, written and read back through this type).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FrfOutput {
    /// The pantograph's name.
    pub pantograph: String,
    /// Its masses.
    pub masses: usize,
    /// Its collector strips.
    pub strips: usize,
    /// The magnitude's column (`magnitude_kg` or `magnitude_m_per_n`, the unit in the name).
    pub quantity: String,
    /// Frequencies, Hz.
    pub frequency_hz: Vec<f64>,
    /// The magnitude, in the unit `quantity` names.
    pub magnitude: Vec<f64>,
    /// The phase, °.
    pub phase_deg: Vec<f64>,
    /// The receptance's resonances over the grid, Hz.
    pub receptance_peaks_hz: Vec<f64>,
    /// `frf.csv`'s text (not in frf.json).
    #[serde(skip)]
    #[schemars(skip)]
    pub csv: String,
}

impl crate::study::Study for FrfStudy {
    const KIND: crate::study::StudyKind = crate::study::StudyKind::PantographFrf;
    type Output = FrfOutput;

    fn check(&self) -> Result<(), CaseError> {
        if self.frequency_hz.len() < 2 {
            return Err(inv(
                "points",
                self.frequency_hz.len(),
                "between 2 and 100000",
            ));
        }
        Ok(())
    }

    fn work(&self) -> usize {
        1
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<FrfOutput, crate::error::SimError> {
        let mut r = Response::of_model(&self.pantograph, self.quantity, &self.frequency_hz)?;
        r.source = format!("pantograph {}", self.name);
        let rec = Response::of_model(&self.pantograph, Quantity::Receptance, &self.frequency_hz)?;
        done();
        Ok(FrfOutput {
            pantograph: self.name.clone(),
            masses: self.pantograph.masses_kg.len(),
            strips: self.pantograph.strips.len(),
            quantity: self.quantity.column().into(),
            frequency_hz: r.frequency_hz.clone(),
            magnitude: r.value.iter().map(|h| h.norm()).collect(),
            phase_deg: r.value.iter().map(|h| h.arg().to_degrees()).collect(),
            receptance_peaks_hz: rec.peaks(),
            csv: r.to_csv(),
        })
    }

    fn files(&self, o: &FrfOutput) -> Vec<crate::study::StudyFile> {
        vec![
            crate::study::StudyFile::text("frf.csv", o.csv.clone()),
            crate::study::StudyFile::text(
                "frf.json",
                serde_json::to_string_pretty(o).unwrap_or_default() + "\n",
            ),
        ]
    }

    fn answer(o: &FrfOutput) -> crate::study::Answer {
        let peaks: Vec<String> = o
            .receptance_peaks_hz
            .iter()
            .map(|&f| format!("{} Hz", crate::analysis::report::significant(f, 3)))
            .collect();
        // The grid's ends as given (exp(ln f) may differ from f in its last digit).
        let given = |f: f64| (f * 1e9).round() / 1e9;
        let (from, to) = (
            o.frequency_hz.first().copied().unwrap_or(0.0),
            o.frequency_hz.last().copied().unwrap_or(0.0),
        );
        crate::study::Answer {
            headline: format!(
                "pantograph {}: {} masses{}; receptance peaks at {} (from {} to {} Hz, {} points)",
                o.pantograph,
                o.masses,
                match o.strips {
                    0 => String::new(),
                    n =>
                        format!(" and {n} strips (a force shared equally, their mean displacement)"),
                },
                if peaks.is_empty() {
                    "none in the range".into()
                } else {
                    peaks.join(", ")
                },
                given(from),
                given(to),
                o.frequency_hz.len()
            ),
            ..Default::default()
        }
    }

    fn figures(&self, o: &FrfOutput) -> Vec<crate::study::Figure> {
        let unit = match self.quantity {
            Quantity::Receptance => "receptance |X/F| [m/N]",
            Quantity::ApparentMass => "apparent mass |F/A| [kg]",
        };
        let title = format!("pantograph {}", o.pantograph);
        let series = |y: &[f64]| {
            vec![crate::study::FigureSeries {
                label: title.clone(),
                x: o.frequency_hz.clone(),
                y: y.to_vec(),
                dots: false,
            }]
        };
        vec![
            crate::study::Figure {
                name: "frf_magnitude".into(),
                title: format!("{title}: magnitude"),
                x_label: "frequency [Hz]".into(),
                y_label: unit.into(),
                series: series(&o.magnitude),
                log_y: true,
            },
            crate::study::Figure {
                name: "frf_phase".into(),
                title: format!("{title}: phase"),
                x_label: "frequency [Hz]".into(),
                y_label: "phase [°]".into(),
                series: series(&o.phase_deg),
                log_y: false,
            },
        ]
    }
}
