//! A pantograph's frequency response at the head, and a lumped model fitted to a measured one
//! (issue 43, item 3: `pcsim pantograph frf` and `pcsim pantograph fit`).
//!
//! The response is the receptance `X₀/F₀` (m/N) of [`Lumped::receptance`], or the apparent mass
//! `F₀/A₀ = −1/(ω² X₀/F₀)` (kg) that pantograph test rigs commonly report. A measured response
//! is read from CSV text with the units in its header (`frequency_hz`, `magnitude_m_per_n` or
//! `magnitude_kg`, `phase_deg`); the fit is a least-squares fit of the chain's masses, springs
//! and dampers to it: argmin's Nelder–Mead on the logarithms of the parameters (bounded to a
//! factor of [`BOUND_FACTOR`] around the starting pantograph, the case's), the residual the
//! complex relative misfit at every frequency, and each parameter's standard uncertainty from
//! the Jacobian at the optimum (`s² (JᵀJ)⁻¹`, `s²` the residual variance).

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use rustfft::num_complex::Complex;
use serde::Serialize;

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
#[derive(Debug, Clone, PartialEq, Serialize)]
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

/// A fit's answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fit {
    /// The fitted pantograph (its uplift and aerodynamic force the starting one's).
    #[serde(skip)]
    pub pantograph: Lumped,
    /// Each parameter.
    pub parameters: Vec<Fitted>,
    /// RMS of the relative complex misfit over the frequencies.
    pub residual_rms: f64,
    /// The same at the start.
    pub start_residual_rms: f64,
    /// Cost evaluations.
    pub evaluations: u64,
    /// The measurement's source.
    pub source: String,
}

impl Fit {
    /// The fitted pantograph as a case's `[[pantographs]]` block named `name`, each fitted value
    /// with the measurement (`label`) as its source; the uplift and the aerodynamic force are the
    /// starting case's (a frequency response does not measure them).
    pub fn case_block(&self, name: &str, label: &str) -> String {
        let source = format!(
            "fitted by pcsim pantograph fit to {label} (residual {:.2} % RMS; uncertainties in fit.json)",
            100.0 * self.residual_rms
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

#[derive(Clone)]
struct Problem<'a> {
    /// Cost evaluations so far.
    count: &'a std::sync::atomic::AtomicU64,
    start: &'a Lumped,
    measured: &'a Response,
    /// Natural logarithms of the bounds.
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Problem<'_> {
    fn cost_of(&self, u: &[f64]) -> f64 {
        self.count
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        // Outside the bounds: the bound's cost plus a steep penalty.
        let mut pen = 0.0;
        let x: Vec<f64> = u
            .iter()
            .zip(self.lo.iter().zip(&self.hi))
            .map(|(&v, (&l, &h))| {
                let c = v.clamp(l, h);
                pen += (v - c) * (v - c);
                c.exp()
            })
            .collect();
        let r = residuals(&with_params(self.start, &x), self.measured);
        r.iter().map(|v| v * v).sum::<f64>() + 1e3 * pen
    }
}

impl CostFunction for Problem<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> Result<Self::Output, ArgminError> {
        Ok(self.cost_of(u))
    }
}

/// Fit the chain of `start` (its number of masses, its values as the start and the centre of
/// the bounds) to `measured`.
pub fn fit(start: &Lumped, measured: &Response) -> Result<Fit, CaseError> {
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
    let x0 = params(start);
    let np = x0.len();
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
    let count = std::sync::atomic::AtomicU64::new(0);
    let problem = Problem {
        count: &count,
        start,
        measured,
        lo: x0.iter().map(|v| (v / BOUND_FACTOR).ln()).collect(),
        hi: x0.iter().map(|v| (v * BOUND_FACTOR).ln()).collect(),
    };
    let mut u: Vec<f64> = x0.iter().map(|v| v.ln()).collect();
    let start_cost = problem.cost_of(&u);
    // Nelder–Mead restarted from its answer until it no longer improves (a simplex collapses
    // on a valley; a fresh one leaves it).
    let mut best = start_cost;
    for round in 0..12 {
        let step = if round == 0 { 0.3 } else { 0.05 };
        let mut simplex = vec![u.clone()];
        for i in 0..np {
            let mut v = u.clone();
            v[i] += step;
            simplex.push(v);
        }
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(1e-14)
            .map_err(|e| inv("fit", "nelder-mead", &e.to_string()))?;
        let res = Executor::new(problem.clone(), solver)
            .configure(|s| s.max_iters(4000))
            .run()
            .map_err(|e| inv("fit", "nelder-mead", &e.to_string()))?;
        let state = res.state();
        let (Some(b), c) = (state.best_param.clone(), state.best_cost) else {
            break;
        };
        let improved = c < best * (1.0 - 1e-9);
        if c <= best {
            u = b;
            best = c;
        }
        if !improved && round > 0 {
            break;
        }
    }
    let x: Vec<f64> = u
        .iter()
        .zip(problem.lo.iter().zip(&problem.hi))
        .map(|(&v, (&l, &h))| v.clamp(l, h).exp())
        .collect();
    let fitted = with_params(start, &x);
    let r = residuals(&fitted, measured);
    let dof = (r.len() as f64 - np as f64).max(1.0);
    let s2 = r.iter().map(|v| v * v).sum::<f64>() / dof;
    // The Jacobian in the logarithms of the parameters, by central differences.
    let h: f64 = 1e-6;
    let mut jac = vec![vec![0.0; np]; r.len()];
    for j in 0..np {
        let mut up = x.clone();
        let mut dn = x.clone();
        up[j] *= h.exp();
        dn[j] *= (-h).exp();
        let (ru, rd) = (
            residuals(&with_params(start, &up), measured),
            residuals(&with_params(start, &dn), measured),
        );
        for i in 0..r.len() {
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
    Ok(Fit {
        pantograph: fitted,
        parameters,
        residual_rms: rms(r.iter().map(|v| v * v).sum()),
        start_residual_rms: rms(start_cost),
        evaluations: count.load(std::sync::atomic::Ordering::Relaxed),
        source: measured.source.clone(),
    })
}
