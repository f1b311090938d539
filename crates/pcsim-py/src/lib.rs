//! The native half of the Python package `pcsim` (the Python half is `python/pcsim`): a thin
//! layer over the core's orchestration. Every run releases the interpreter (`Python::detach`),
//! summaries and tables cross as the JSON the CLI writes, time series as numpy arrays handed
//! over once. Errors of the core become `ValueError` with the core's message (naming the field).
// No production function over 100 lines (clippy.toml's threshold; issue 52): a long function
// is split into named parts. Tests are exempt (a scenario reads best whole).
#![cfg_attr(not(test), deny(clippy::too_many_lines))]

use numpy::IntoPyArray;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use pcsim_core::analysis::eva::{EvaRow, EvaSettings};
use pcsim_core::analysis::events::{run_errors, AllowedErrors, RunErrorKind};
use pcsim_core::analysis::report::timeseries_columns;
use pcsim_core::analysis::sweep::{parallel_map, Shard};
use pcsim_core::compile::Budget;
use pcsim_core::input::overrides::{with_overrides, OverrideValue};
use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeSession};
use pcsim_core::study::specs::{EvaSweepSpec, GridSpec, WindowSweepSpec};
use pcsim_core::study::sweeps::{run_quietly, validation_runs, WindowRow};
use pcsim_core::study::validate::ValidationPlan;
use pcsim_core::study::window_search::Tolerances;

fn err(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Run `f`, turning a panic into a `RuntimeError` with its message: no `PanicException` (a
/// `BaseException`, which `except Exception` misses) reaches the user (issue 19, item 6).
fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(PyRuntimeError::new_err(format!(
                "pcsim failed internally ({msg}); please report it with the case"
            )))
        }
    }
}

/// How often a run looks for Ctrl-C (a signal waiting in the interpreter).
const SIGNAL_EVERY: std::time::Duration = std::time::Duration::from_millis(50);

/// A case: a catenary, its pantographs and a run (TOML, SI units as the field names say).
#[pyclass(module = "pcsim._pcsim", frozen)]
#[derive(Clone)]
struct Case {
    inner: pcsim_core::Case,
    /// The ranges the case's text gives its values (for `run(sensitivity=True)`).
    ranges: Vec<pcsim_core::input::RangedValue>,
    /// The paths set by `with_overrides` (their ranges are not varied).
    fixed: Vec<String>,
}

#[pymethods]
impl Case {
    /// An embedded preset by name (see `presets()`).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Case> {
        let (inner, _, ranges) =
            pcsim_core::Case::from_toml_str_with_ranges(presets::find(name).map_err(err)?.toml)
                .map_err(err)?;
        Ok(Case {
            inner,
            ranges,
            fixed: Vec::new(),
        })
    }

    /// A case from TOML text (values plain or `{ value, source }`).
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Case> {
        guarded(|| {
            let (inner, _, ranges) =
                pcsim_core::Case::from_toml_str_with_ranges(text).map_err(err)?;
            Ok(Case {
                inner,
                ranges,
                fixed: Vec::new(),
            })
        })
    }

    /// A case from a TOML file.
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Case> {
        guarded(|| {
            // The core's one case loader and its wording, as the CLI's.
            let text = std::fs::File::open(&path).and_then(|f| {
                pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
            });
            let (inner, ranges) =
                pcsim_core::input::case_and_ranges_from_file(&path.display().to_string(), text)
                    .map_err(err)?;
            Ok(Case {
                inner,
                ranges,
                fixed: Vec::new(),
            })
        })
    }

    /// The case with values replaced by dotted path, each in the field's own unit:
    /// `{"run.speed_kmh": 300, "catenary.contact_wire.tension_n": 21000.0}`.
    fn with_overrides(&self, overrides: &Bound<'_, PyDict>) -> PyResult<Case> {
        guarded(|| {
            let mut list = Vec::with_capacity(overrides.len());
            for (k, v) in overrides.iter() {
                let path: String = k.extract()?;
                let value = if let Ok(b) = v.extract::<bool>() {
                    OverrideValue::Bool(b)
                } else if let Ok(i) = v.extract::<i64>() {
                    OverrideValue::Integer(i)
                } else if let Ok(x) = v.extract::<f64>() {
                    OverrideValue::Number(x)
                } else if let Ok(s) = v.extract::<String>() {
                    OverrideValue::Text(s)
                } else if let Ok(l) = v.extract::<Vec<f64>>() {
                    OverrideValue::Numbers(l)
                } else {
                    return Err(err(format!(
                        "override `{path}`: give a number, a bool, a string or a list of numbers"
                    )));
                };
                list.push((path, value));
            }
            let inner = with_overrides(&self.inner, &list).map_err(err)?;
            inner.validate().map_err(err)?;
            let mut fixed = self.fixed.clone();
            fixed.extend(list.into_iter().map(|(p, _)| p));
            Ok(Case {
                inner,
                ranges: self.ranges.clone(),
                fixed,
            })
        })
    }

    /// The value at a dotted path (`"run.start_m"`, `"pantographs[0].masses_kg"`), in the
    /// field's unit; `ValueError` if there is none.
    fn get<'py>(&self, py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyAny>> {
        guarded(|| {
            let v = pcsim_core::input::overrides::value_at(&self.inner, path).map_err(err)?;
            to_py(py, &v)
        })
    }

    /// The case as TOML text (plain values).
    fn to_toml(&self) -> String {
        self.inner.to_toml_string()
    }

    /// Check every value: the warnings, or a `ValueError` naming the field and value.
    fn validate(&self) -> PyResult<Vec<String>> {
        guarded(|| {
            Ok(self
                .inner
                .validate()
                .map_err(err)?
                .into_iter()
                .map(|w| w.0)
                .collect())
        })
    }

    /// Pickling: by the TOML text.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let ctor = py.get_type::<Case>().getattr("from_toml")?;
        let args = PyTuple::new(py, [slf.get().inner.to_toml_string()])?;
        PyTuple::new(py, [ctor.into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "Case({:?}, {} km/h)",
            pcsim_core::analysis::report::case_name(&self.inner),
            self.inner.run.speed_kmh
        )
    }
}

fn to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(to_py(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
    })
}

/// A run handed to Python: its summary (the core's `RunSummary`, the CLI's summary.json), its
/// time-series columns as numpy arrays, and the reason it is refused (an error-level event not
/// accepted) if it is.
fn hand_over<'py>(
    py: Python<'py>,
    o: &pcsim_core::study::run::RunStudyOutput,
    allowed: AllowedErrors,
) -> PyResult<Bound<'py, PyTuple>> {
    let json = serde_json::to_string(&o.summary).map_err(err)?;
    let out = o.run.as_ref().expect("a run just made");
    let cols = PyList::empty(py);
    for c in timeseries_columns(out) {
        cols.append((c.name, c.values.into_pyarray(py)))?;
    }
    let errors = run_errors(out);
    let refused = allowed.first_refused(&errors).map(|e| {
        let arg = match e.kind {
            RunErrorKind::Dewirement => "allow_dewirement=True",
            RunErrorKind::ContactLoss => "allow_contact_loss=True",
        };
        format!(
            "{} (the result is attached as .result; pass {arg} to accept the run)",
            e.message
        )
    });
    PyTuple::new(
        py,
        [
            json.into_pyobject(py)?.into_any(),
            cols.into_any(),
            refused.into_pyobject(py)?.into_any(),
        ],
    )
}

/// The core's run study of `case` on `threads` (the one orchestration of a run: the CLI's too).
fn run_study(case: &pcsim_core::Case, threads: usize) -> pcsim_core::study::run::RunStudy {
    pcsim_core::study::run::RunStudy {
        case: case.clone(),
        ranges: Vec::new(),
        fixed: Vec::new(),
        overrides: Vec::new(),
        spec: pcsim_core::study::run::RunSpec {
            threads,
            ..Default::default()
        },
        budget: Default::default(),
        jobs: None,
    }
}

/// Run one case (the interpreter is released meanwhile): `(summary_json, [(column, array)])`.
/// Ctrl-C stops it between chunks of steps (the run loop's progress checks, every 256 steps) and
/// raises `KeyboardInterrupt`. `threads`: the run's threads (the core's `team::usable_threads`
/// rule; the same numbers on any count). `verify`: the refined run and the stiffer contact's
/// (the CLI's `--verify`), in the summary's `verification`. `sensitivity`: the case's ranged
/// values one at a time and `sensitivity_samples` runs drawn from `sensitivity_seed` (the CLI's
/// `--sensitivity`), in the summary's `sensitivity`.
#[pyfunction]
#[pyo3(signature = (case, threads=1, allow_dewirement=false, allow_contact_loss=false, verify=false, sensitivity=false, sensitivity_samples=None, sensitivity_seed=None, sensitivity_max_runs=None, allow_failed_runs=false))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    case: &Case,
    threads: usize,
    allow_dewirement: bool,
    allow_contact_loss: bool,
    verify: bool,
    sensitivity: bool,
    sensitivity_samples: Option<usize>,
    sensitivity_seed: Option<u64>,
    sensitivity_max_runs: Option<usize>,
    allow_failed_runs: bool,
) -> PyResult<Bound<'py, PyTuple>> {
    use pcsim_core::analysis::sensitivity::SensitivitySpec;
    use pcsim_core::study::Study;
    let d = SensitivitySpec::default();
    let allowed = AllowedErrors {
        dewirement: allow_dewirement,
        contact_loss: allow_contact_loss,
    };
    guarded(|| {
        use pcsim_core::solve::team;
        let threads = team::usable_threads(threads)
            .map_err(|e| PyValueError::new_err(format!("threads={e}")))?;
        // Busy cores: fewer threads, and a RuntimeWarning that says why (the CLI's rule).
        let threads = if threads > 1 {
            let (n, why) = team::threads_for_idle(
                threads,
                team::idle_cores(std::time::Duration::from_millis(200)),
            );
            if let Some(why) = why {
                let cat = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                PyErr::warn(py, &cat, &std::ffi::CString::new(why).map_err(err)?, 1)?;
            }
            n
        } else {
            threads
        };
        // The core's run study, as the CLI's `pcsim run` fills it.
        let mut study = run_study(&case.inner, threads);
        study.ranges = case.ranges.clone();
        study.fixed = case.fixed.clone();
        study.spec.verify = verify;
        study.spec.allowed = allowed;
        study.spec.sensitivity = sensitivity.then_some(SensitivitySpec {
            samples: sensitivity_samples.unwrap_or(d.samples),
            seed: sensitivity_seed.unwrap_or(d.seed),
            max_runs: sensitivity_max_runs.unwrap_or(d.max_runs),
            allow_failed_runs,
        });
        // Refused by the keyword's name, as the CLI names its flag.
        study
            .check()
            .map_err(|e| {
                pcsim_core::study::specs::with_flags(
                    e,
                    &[
                        ("sensitivity.samples", "sensitivity_samples"),
                        ("sensitivity.max_runs", "sensitivity_max_runs"),
                    ],
                )
            })
            .map_err(err)?;
        let mut interrupted: Option<PyErr> = None;
        let res = py.detach(|| {
            let mut last = std::time::Instant::now();
            study.run_with(&mut |_| {
                if last.elapsed() < SIGNAL_EVERY {
                    return true;
                }
                last = std::time::Instant::now();
                match Python::attach(|py| py.check_signals()) {
                    Ok(()) => true,
                    Err(e) => {
                        interrupted = Some(e);
                        false
                    }
                }
            })
        });
        if let Some(e) = interrupted {
            return Err(e);
        }
        let o = res.map_err(err)?;
        if let Some(s) = &o.summary.sensitivity {
            s.check().map_err(err)?;
        }
        hand_over(py, &o, allowed)
    })
}

/// Run several cases on up to `jobs` threads (all cores by default), in order.
#[pyfunction]
#[pyo3(signature = (cases, jobs=None, allow_dewirement=false, allow_contact_loss=false))]
fn run_many<'py>(
    py: Python<'py>,
    cases: Vec<Case>,
    jobs: Option<usize>,
    allow_dewirement: bool,
    allow_contact_loss: bool,
) -> PyResult<Bound<'py, PyList>> {
    let allowed = AllowedErrors {
        dewirement: allow_dewirement,
        contact_loss: allow_contact_loss,
    };
    guarded(|| {
        let studies: Vec<_> = cases.iter().map(|c| run_study(&c.inner, 1)).collect();
        let outs = py.detach(move || parallel_map(&studies, jobs, |s| s.run_with(&mut |_| true)));
        let list = PyList::empty(py);
        for o in outs {
            list.append(hand_over(py, &o.map_err(err)?, allowed)?)?;
        }
        Ok(list)
    })
}

/// The grid of a sweep from the keyword arguments (the seeds checked against the case, the
/// shard parsed), as the CLI builds it.
fn grid_spec(
    case: &pcsim_core::Case,
    speeds_kmh: Vec<f64>,
    tensions_n: Vec<f64>,
    seeds: Option<usize>,
    shard: Option<(usize, usize)>,
) -> Result<GridSpec, String> {
    let seeds = pcsim_core::analysis::sweep::check_seeds(seeds, case)
        .map_err(|e| format!("seeds = {}: {e}", seeds.unwrap_or(1)))?;
    let shard = match shard {
        None => Shard::ALL,
        Some((i, n)) => Shard::parse(&format!("{i}/{n}")).map_err(|e| e.to_string())?,
    };
    Ok(GridSpec {
        speeds_kmh,
        tensions_n,
        dampings: Vec::new(),
        seeds,
        shard,
    })
}

/// The resource budget of a sweep (the CLI's `--max-steps`, `--max-memory-gb`): the core's one
/// conversion and check.
fn budget(max_steps: Option<u64>, max_memory_gb: Option<f64>) -> Result<Budget, String> {
    pcsim_core::study::specs::budget_of(max_steps, max_memory_gb).map_err(|e| e.to_string())
}

/// EVA over speeds (km/h) × tensions (N): the rows of `eva.csv` as JSON text, by the core's one
/// sweep (the CLI's), with seeds, a shard `(index, count)` and the resource budget.
#[pyfunction]
#[pyo3(signature = (case, speeds_kmh, tensions_n, step_m=1.0, tolerance_j=0.01, fraction=0.99, jobs=None, seeds=None, shard=None, max_steps=None, max_memory_gb=None))]
#[allow(clippy::too_many_arguments)]
fn eva(
    py: Python<'_>,
    case: &Case,
    speeds_kmh: Vec<f64>,
    tensions_n: Vec<f64>,
    step_m: f64,
    tolerance_j: f64,
    fraction: f64,
    jobs: Option<usize>,
    seeds: Option<usize>,
    shard: Option<(usize, usize)>,
    max_steps: Option<u64>,
    max_memory_gb: Option<f64>,
) -> PyResult<String> {
    guarded(|| {
        let base = case.inner.clone();
        let rows = py.detach(move || -> Result<Vec<EvaRow>, String> {
            let b = budget(max_steps, max_memory_gb)?;
            // The keyword arguments become the core's spec: its checks, its sweep.
            let spec = EvaSweepSpec {
                grid: grid_spec(&base, speeds_kmh, tensions_n, seeds, shard)?,
                settings: EvaSettings {
                    step_m,
                    tolerance_j,
                    fraction,
                    budget: b,
                    ..EvaSettings::default()
                },
            };
            spec.check().map_err(|e| e.to_string())?;
            let (_, mine) = spec.grid.jobs(&base).map_err(|e| e.to_string())?;
            Ok(spec
                .run(&mine, &b, jobs, &|| ())
                .map_err(|e| e.to_string())?
                .into_iter()
                .map(|c| c.row)
                .collect())
        });
        serde_json::to_string(&rows.map_err(err)?).map_err(err)
    })
}

/// The accuracy-based window length over speeds (km/h) × tensions (N): the rows of
/// `window.csv` as JSON text, by the core's one sweep (the CLI's `pcsim window`). The case's
/// window follows `pantograph` (the case's `run.window_pantograph`, by default the leading one);
/// tolerances in %, lengths in m.
#[pyfunction]
#[pyo3(signature = (case, speeds_kmh, tensions_n, mean_tol_pct=1.0, sigma_tol_pct=3.0, max_tol_pct=5.0, min_window_m=None, max_window_m=400.0, coarse_m=20.0, resolution_m=1.0, jobs=None, seeds=None, shard=None, max_steps=None, max_memory_gb=None, full_scan=true, pantograph=None))]
#[allow(clippy::too_many_arguments)]
fn window(
    py: Python<'_>,
    case: &Case,
    speeds_kmh: Vec<f64>,
    tensions_n: Vec<f64>,
    mean_tol_pct: f64,
    sigma_tol_pct: f64,
    max_tol_pct: f64,
    min_window_m: Option<f64>,
    max_window_m: f64,
    coarse_m: f64,
    resolution_m: f64,
    jobs: Option<usize>,
    seeds: Option<usize>,
    shard: Option<(usize, usize)>,
    max_steps: Option<u64>,
    max_memory_gb: Option<f64>,
    full_scan: bool,
    pantograph: Option<String>,
) -> PyResult<String> {
    guarded(|| {
        let base = with_window_pantograph(&case.inner, pantograph);
        let rows = py.detach(move || -> Result<Vec<WindowRow>, String> {
            let spec = WindowSweepSpec {
                grid: grid_spec(&base, speeds_kmh, tensions_n, seeds, shard)?,
                tolerances: Tolerances {
                    mean_pct: mean_tol_pct,
                    sigma_pct: sigma_tol_pct,
                    max_pct: max_tol_pct,
                },
                min_window_m,
                max_window_m,
                coarse_m,
                resolution_m,
                coarse_only: !full_scan,
            };
            // The tolerances and the search are checked by the core's spec, as for the CLI.
            spec.check(&base).map_err(|e| e.to_string())?;
            let (_, mine) = spec.jobs(&base).map_err(|e| e.to_string())?;
            let b = budget(max_steps, max_memory_gb)?;
            Ok(spec
                .run(&base, &mine, &b, jobs, &|| ())
                .map_err(|e| e.to_string())?
                .into_iter()
                .map(|c| c.row)
                .collect())
        });
        serde_json::to_string(&rows.map_err(err)?).map_err(err)
    })
}

/// A validation (`en50318-2002` or `seed-table1`), or a user's targets (`targets_toml`, named
/// `targets_label`), optionally run on a user's case instead of the preset (`case`, named
/// `case_label`): the report of `pcsim validate --json`, by the core's one validation run.
#[pyfunction]
#[pyo3(signature = (name, jobs=None, case=None, case_label=None, targets_toml=None, targets_label=None, verify=false))]
#[allow(clippy::too_many_arguments)]
fn validate(
    py: Python<'_>,
    name: &str,
    jobs: Option<usize>,
    case: Option<&Case>,
    case_label: Option<String>,
    targets_toml: Option<String>,
    targets_label: Option<String>,
    verify: bool,
) -> PyResult<String> {
    guarded(|| {
        let label = case_label.as_deref().unwrap_or("case");
        let plan = match (&targets_toml, case) {
            (Some(text), c) => ValidationPlan::from_targets_on(
                text,
                targets_label.as_deref().unwrap_or("targets"),
                c.map(|c| (c.inner.clone(), label)),
            ),
            (None, Some(c)) => {
                ValidationPlan::new(name).and_then(|p| p.on_case(c.inner.clone(), label))
            }
            (None, None) => ValidationPlan::new(name),
        }
        .map_err(err)?;
        let report = py.detach(move || -> Result<String, String> {
            let b = Budget::default();
            let (runs, mut report) =
                validation_runs(&plan, jobs, &|c| run_quietly(c, &b)).map_err(|e| e.to_string())?;
            if verify {
                let outs: Vec<_> = runs.into_iter().map(|r| r.0).collect();
                plan.verify(&outs, &mut report, &b, jobs)
                    .map_err(|e| e.to_string())?;
            }
            serde_json::to_string(&report).map_err(|e| e.to_string())
        });
        report.map_err(err)
    })
}

/// A response handed to Python: frequencies, magnitudes, phases in degrees, the magnitude's
/// column name (its unit).
type Frf = (Vec<f64>, Vec<f64>, Vec<f64>, String);

/// The frequency response at the head of `case`'s pantograph `pantograph` (the CLI's `pcsim
/// pantograph frf`): `(frequency_hz, magnitude, phase_deg, unit)`.
#[pyfunction]
#[pyo3(signature = (case, pantograph=None, quantity="apparent-mass", from_hz=0.1, to_hz=20.0, points=200))]
fn pantograph_frf(
    case: &Case,
    pantograph: Option<String>,
    quantity: &str,
    from_hz: f64,
    to_hz: f64,
    points: usize,
) -> PyResult<Frf> {
    use pcsim_core::study::frf::{Quantity, Response};
    guarded(|| {
        let q = match quantity {
            "apparent-mass" => Quantity::ApparentMass,
            "receptance" => Quantity::Receptance,
            other => {
                return Err(PyValueError::new_err(format!(
                    "quantity={other:?}: \"apparent-mass\" or \"receptance\""
                )))
            }
        };
        let (_, p) = pcsim_core::compile::lumped_pantograph(&case.inner, pantograph.as_deref())
            .map_err(err)?;
        let f = Response::log_grid(from_hz, to_hz, points).map_err(err)?;
        let r = Response::of_model(&p, q, &f).map_err(err)?;
        Ok((
            r.frequency_hz,
            r.value.iter().map(|h| h.norm()).collect(),
            r.value.iter().map(|h| h.arg().to_degrees()).collect(),
            q.column().to_string(),
        ))
    })
}

/// `case`'s pantograph fitted to a measured response (CSV text `measured_csv`, named `label`):
/// the CLI's `pcsim pantograph fit` — `(fit_json, case_block)`.
#[pyfunction]
#[pyo3(signature = (measured_csv, label, case, pantograph=None, starts=None, seed=None, max_residual_percent=None))]
#[allow(clippy::too_many_arguments)]
fn pantograph_fit(
    py: Python<'_>,
    measured_csv: &str,
    label: &str,
    case: &Case,
    pantograph: Option<String>,
    starts: Option<usize>,
    seed: Option<u64>,
    max_residual_percent: Option<f64>,
) -> PyResult<(String, String)> {
    use pcsim_core::study::frf::{fit_with, FitSpec, Response};
    guarded(|| {
        let (name, p) = pcsim_core::compile::lumped_pantograph(&case.inner, pantograph.as_deref())
            .map_err(err)?;
        let m = Response::from_csv(measured_csv, label).map_err(err)?;
        let d = FitSpec::default();
        let spec = FitSpec {
            starts: starts.unwrap_or(d.starts),
            seed: seed.unwrap_or(d.seed),
            max_residual_rms: max_residual_percent.map_or(d.max_residual_rms, |x| x / 100.0),
        };
        let r = py
            .detach(|| {
                let r = fit_with(&p, &m, &spec, &mut |_, _| {})?;
                r.check(&p, &m)?;
                Ok::<_, pcsim_core::CaseError>(r)
            })
            .map_err(err)?;
        Ok((
            serde_json::to_string(&r.record).map_err(err)?,
            r.case_block(&name, label),
        ))
    })
}

/// A run's summary (`Result.summary` as JSON, `kind` "run") or the current-collection study's
/// `wear.json` (`kind` "wear": its arcing) against the acceptance criteria, by the core's one
/// assessment (the CLI's `pcsim assess`): the assessment as JSON. `criteria_toml` adds a
/// user's criteria (status `user`, each with its source).
#[pyfunction]
#[pyo3(signature = (what_json, kind, system=None, criteria_toml=None))]
fn assess(
    what_json: &str,
    kind: &str,
    system: Option<&str>,
    criteria_toml: Option<&str>,
) -> PyResult<String> {
    use pcsim_core::analysis::assess::{assess, AssessInput};
    use pcsim_core::input::criteria::{self, System};
    guarded(|| {
        // A run's summary.json, or the current-collection study's wear.json (its arcing).
        let input = match kind {
            "run" => AssessInput::from_summary_json(what_json),
            "wear" => AssessInput::from_wear_json(what_json),
            k => {
                return Err(err(format!(
                    "assess: a run or a wear study, not a {k} study"
                )))
            }
        }
        .map_err(err)?;
        let system = system
            .map(|s| System::parse_or_explain(s).map_err(|e| err(format!("system = {e}"))))
            .transpose()?;
        let mut list = criteria::builtin();
        if let Some(t) = criteria_toml {
            let user = criteria::user_file(t).map_err(|e| err(format!("criteria: {e}")))?;
            list = criteria::merged(list, user);
        }
        serde_json::to_string(&assess(&input, &list, system)).map_err(err)
    })
}

/// A design spec's text with its base case (a `base.file` read relative to `base_dir`, within
/// the input limit), by the core's one loader.
fn design_of(spec_toml: &str, base_dir: &str) -> PyResult<pcsim_core::study::design::Design> {
    let dir = std::path::PathBuf::from(base_dir);
    let read = |f: &str| {
        let f = std::fs::File::open(dir.join(f))?;
        pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
    };
    pcsim_core::study::design::Design::from_spec_text(spec_toml, &read)
        .map_err(|e| err(format!("design spec: {e}")))
}

/// The journal's columns of a design search (design.csv's header).
#[pyfunction]
fn design_header(spec_toml: &str, base_dir: &str) -> PyResult<Vec<String>> {
    guarded(|| Ok(design_of(spec_toml, base_dir)?.journal_header()))
}

/// One design's evaluation (every speed of the spec), as its journal row: what a Dask worker
/// runs for `pcsim.design(..., client=...)`.
#[pyfunction]
fn design_evaluate(
    py: Python<'_>,
    spec_toml: &str,
    base_dir: &str,
    x: Vec<f64>,
) -> PyResult<Vec<String>> {
    guarded(|| {
        let d = design_of(spec_toml, base_dir)?;
        if x.len() != d.spec.variables.len() {
            return Err(err(format!(
                "x: {} values for the spec's {} variables",
                x.len(),
                d.spec.variables.len()
            )));
        }
        let e = py.detach(|| d.evaluate(&x, Some(1)).0);
        Ok(d.journal_row(&e))
    })
}

/// A batch evaluator that calls a Python function (a Dask client's map): given the designs'
/// values, it returns their journal rows, which are read back and checked (the fingerprint, the
/// values).
struct PyEvaluator {
    evaluate: Py<PyAny>,
}

impl pcsim_core::study::design::Evaluator for PyEvaluator {
    fn evaluate(
        &self,
        design: &pcsim_core::study::design::Design,
        xs: &[Vec<f64>],
    ) -> Result<Vec<pcsim_core::study::design::Evaluation>, String> {
        let rows: Vec<Vec<String>> = Python::attach(|py| {
            self.evaluate
                .call1(py, (xs.to_vec(),))
                .and_then(|r| r.extract(py))
                .map_err(|e| format!("the evaluator raised: {e}"))
        })?;
        let header = design.journal_header();
        rows.iter()
            .map(|r| design.journal_read(&header, r).map_err(|e| e.to_string()))
            .collect()
    }
}

/// The design search of a spec (the CLI's `pcsim design`): `(answer_json, header)`. `journal`:
/// the rows of an earlier run's journal (resumed: not run again); `on_batch(rows)` receives the
/// new rows batch by batch (to append them to a journal); `evaluate(xs) -> rows` runs the
/// batches elsewhere (Dask), else they run here on `jobs` threads. Ctrl-C stops the search
/// between batches and raises `KeyboardInterrupt` (the journal keeps what was run).
#[pyfunction]
#[pyo3(signature = (spec_toml, base_dir, journal=Vec::new(), on_batch=None, evaluate=None, jobs=None))]
fn design(
    py: Python<'_>,
    spec_toml: &str,
    base_dir: &str,
    journal: Vec<Vec<String>>,
    on_batch: Option<Py<PyAny>>,
    evaluate: Option<Py<PyAny>>,
    jobs: Option<usize>,
) -> PyResult<(String, Vec<String>)> {
    use pcsim_core::study::design::{search, Evaluator, Local};
    guarded(|| {
        let d = design_of(spec_toml, base_dir)?;
        let header = d.journal_header();
        let mut rows = journal.into_iter();
        let first = rows.next();
        let journal = match first {
            None => Vec::new(),
            Some(h) if h == header => rows
                .enumerate()
                .map(|(k, r)| {
                    d.journal_read(&header, &r)
                        .map_err(|e| err(format!("journal row {}: {e}", k + 1)))
                })
                .collect::<PyResult<Vec<_>>>()?,
            Some(h) => {
                return Err(err(format!(
                    "journal: its header ({}) is not this spec's ({})",
                    h.join(","),
                    header.join(",")
                )))
            }
        };
        let local = Local { jobs };
        let remote = evaluate.map(|e| PyEvaluator { evaluate: e });
        let evaluator: &dyn Evaluator = match &remote {
            Some(r) => r,
            None => &local,
        };
        let mut interrupted: Option<PyErr> = None;
        let mut callback_error: Option<PyErr> = None;
        let result = py.detach(|| {
            search(&d, journal, evaluator, jobs, &mut |fresh| {
                Python::attach(|py| {
                    if let Some(f) = &on_batch {
                        let rows: Vec<Vec<String>> =
                            fresh.iter().map(|e| d.journal_row(e)).collect();
                        if let Err(e) = f.call1(py, (rows,)) {
                            callback_error = Some(e);
                            return false;
                        }
                    }
                    match py.check_signals() {
                        Ok(()) => true,
                        Err(e) => {
                            interrupted = Some(e);
                            false
                        }
                    }
                })
            })
        });
        if let Some(e) = interrupted.or(callback_error) {
            return Err(e);
        }
        let r = result.map_err(err)?;
        if let Some(e) = r.confirmation_error(&d) {
            return Err(err(e));
        }
        Ok((serde_json::to_string(&r.to_json(&d)).map_err(err)?, header))
    })
}

/// What [`study`] hands Python: the kind, the answer as JSON, the files as `(name, text)`.
type StudyRan = (String, String, Vec<(String, String)>);

/// A study written as a spec file (its `kind` names it; the core's table builds it, as for
/// `pcsim study`): its case is a preset's name or a file read relative to `base_dir`. Returns
/// `(kind, answer_json, files)`, files as `(name, text)` in the order the CLI writes them.
#[pyfunction]
#[pyo3(signature = (spec_toml, base_dir="."))]
fn study(spec_toml: &str, base_dir: &str) -> PyResult<StudyRan> {
    let dir = std::path::PathBuf::from(base_dir);
    let load = |name: &str| -> Result<(pcsim_core::Case, String), pcsim_core::CaseError> {
        let path = dir.join(name);
        let file = path.is_file().then(|| {
            let read = std::fs::File::open(&path).and_then(|f| {
                pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
            });
            (path.display().to_string(), read)
        });
        pcsim_core::study::case_named(name, file)
    };
    let s = pcsim_core::study::from_spec(spec_toml, &load).map_err(err)?;
    s.check().map_err(err)?;
    let kind = s.kind().name().to_string();
    let ran = guarded(|| s.run_erased(&|| {}).map_err(err))?;
    let files = (ran.files.into_iter())
        .map(|f| (f.name, String::from_utf8_lossy(&f.bytes).into_owned()))
        .collect();
    Ok((
        kind,
        serde_json::to_string(&ran.answer).map_err(err)?,
        files,
    ))
}

/// The names of the embedded presets.
#[pyfunction]
fn presets_list() -> Vec<String> {
    presets::PRESETS
        .iter()
        .map(|p| p.name.to_string())
        .collect()
}

/// The tiny cases of every geometry family (`pcsim_core::zoo::geometries`), as `(name,
/// case)`: the cases every front end's table of docs/matrix.md is checked on.
#[pyfunction]
fn zoo_geometries() -> Vec<(String, Case)> {
    pcsim_core::zoo::geometries::geometries()
        .into_iter()
        .map(|(g, c)| {
            (
                g.to_string(),
                Case {
                    inner: c,
                    ranges: Vec::new(),
                    fixed: Vec::new(),
                },
            )
        })
        .collect()
}

/// `case` with the pantograph a real-time window follows set (`run.window_pantograph`), where a
/// keyword gives one; the core resolves it and refuses one the case does not have.
fn with_window_pantograph(case: &pcsim_core::Case, pantograph: Option<String>) -> pcsim_core::Case {
    let mut c = case.clone();
    if pantograph.is_some() {
        c.run.window_pantograph = pantograph;
    }
    c
}

/// The moving-window catenary for hardware in the loop (`coupling="hil"`: the measured contact
/// force and position are inputs) or software in the loop (`"sil"`: pcsim's pantograph). It
/// translates the core's real-time session, which owns the step contract (README, "The real-time
/// step contract"); the window carries the pantograph it follows (`pantograph`: "leading",
/// "trailing", a name or an index; by default the case's `run.window_pantograph`, else the
/// leading one).
#[pyclass(module = "pcsim._pcsim")]
struct RealtimeCatenary {
    inner: RealtimeSession,
}

#[pymethods]
impl RealtimeCatenary {
    #[new]
    #[pyo3(signature = (case, window_m=215.0, coupling="hil", pantograph=None))]
    fn new(
        case: &Case,
        window_m: f64,
        coupling: &str,
        pantograph: Option<String>,
    ) -> PyResult<Self> {
        guarded(|| {
            let coupling = match coupling {
                "hil" => Coupling::Hil,
                "sil" => Coupling::Sil,
                other => return Err(err(format!("coupling `{other}`: use \"hil\" or \"sil\""))),
            };
            Ok(Self {
                inner: RealtimeSession::new(
                    &with_window_pantograph(&case.inner, pantograph),
                    window_m,
                    coupling,
                )
                .map_err(err)?,
            })
        })
    }

    /// One fixed step with the contact force (N, pushing the wire up) and the pantograph's
    /// track position (m); returns the contact-wire height (m) and vertical velocity (m/s) at
    /// the contact point. An input the window cannot take, or a step rolled back, raises
    /// `ValueError` with the reason (its code in parentheses); the catenary is then unchanged.
    fn step(&mut self, force_n: f64, track_position_m: f64) -> PyResult<(f64, f64)> {
        guarded(|| {
            let o = self.inner.step(force_n, track_position_m).map_err(err)?;
            Ok((o.wire_height_m, o.wire_velocity_m_s))
        })
    }

    /// [`step`] without raising: `("ok", height_m, velocity_m_s)`, or `(code, None, None)` where
    /// `code` names why the step was not taken (`force_out_of_bound`, `not_finite`,
    /// `outside_model`, `behind_window`, `ahead_of_window`, `too_fast`, `rolled_back`).
    fn try_step(
        &mut self,
        force_n: f64,
        track_position_m: f64,
    ) -> (&'static str, Option<f64>, Option<f64>) {
        match self.inner.step(force_n, track_position_m) {
            Ok(o) => ("ok", Some(o.wire_height_m), Some(o.wire_velocity_m_s)),
            Err(e) => (e.code(), None, None),
        }
    }

    /// The fixed time step, s.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.inner.dt_s()
    }

    /// The case's start: the leading pantograph's track position at t = 0, m.
    #[getter]
    fn start_position_m(&self) -> f64 {
        self.inner.start_position_m()
    }

    /// The bound on the input contact force, N.
    #[getter]
    fn force_limit_n(&self) -> f64 {
        self.inner.force_limit_n()
    }

    /// Window moves so far.
    #[getter]
    fn moves(&self) -> usize {
        self.inner.moves()
    }

    /// Modes per wire in the window.
    #[getter]
    fn n_modes(&self) -> usize {
        self.inner.n_modes()
    }
}

/// Test hook: panic inside a guarded call with `message` (the tests check that it reaches
/// Python as a `RuntimeError`, never a `PanicException`).
#[pyfunction]
fn _test_panic(message: &str) -> PyResult<()> {
    guarded(|| panic!("{message}"))
}

#[pymodule]
fn _pcsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Case>()?;
    m.add_class::<RealtimeCatenary>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_many, m)?)?;
    m.add_function(wrap_pyfunction!(eva, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(assess, m)?)?;
    m.add_function(wrap_pyfunction!(window, m)?)?;
    m.add_function(wrap_pyfunction!(presets_list, m)?)?;
    m.add_function(wrap_pyfunction!(study, m)?)?;
    m.add_function(wrap_pyfunction!(zoo_geometries, m)?)?;
    m.add_function(wrap_pyfunction!(design, m)?)?;
    m.add_function(wrap_pyfunction!(pantograph_frf, m)?)?;
    m.add_function(wrap_pyfunction!(pantograph_fit, m)?)?;
    m.add_function(wrap_pyfunction!(design_header, m)?)?;
    m.add_function(wrap_pyfunction!(design_evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(_test_panic, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
