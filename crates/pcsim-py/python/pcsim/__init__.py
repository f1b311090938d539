"""pcsim: pantograph–catenary dynamic interaction (modal catenary model, EN 50318 statistics,
energy distribution and EVA, the real-time window for HIL).

A thin layer over the Rust core: every run releases the interpreter, so threads run in
parallel. Units are SI as the names say (``speed_kmh`` in km/h where the name says so).

    import pcsim
    case = pcsim.Case.preset("en50318-2002")
    case = case.with_overrides({"run.speed_kmh": 300, "catenary.contact_wire.tension_n": 21000.0})
    res = pcsim.run(case)
    res.summary["pantographs"][0]["stats"]["std_n"]     # N
    res.timeseries["leading_force_filtered_n"]          # numpy array, N
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import _pcsim
from ._pcsim import Case, RealtimeCatenary

__version__ = _pcsim.__version__

__all__ = [
    "Case",
    "Result",
    "RunEventError",
    "RealtimeCatenary",
    "run",
    "window",
    "sweep",
    "eva",
    "validate",
    "assess",
    "design",
    "pantograph_frf",
    "pantograph_fit",
    "presets",
    "study",
]


class RunEventError(ValueError):
    """A run had an error-level event (a dewirement, contact lost over 10 % of the analysis
    section) that was not accepted by ``allow_dewirement=True`` or ``allow_contact_loss=True``:
    the CLI's exit status 2. The run's result is in ``.result`` (its ``errors`` name every
    event), as the CLI writes its outputs."""

    def __init__(self, message: str, result: "Result"):
        super().__init__(message)
        self.result = result

    def __reduce__(self):
        return (RunEventError, (self.args[0], self.result))


class Result:
    """One run.

    ``summary``: a dict with the content of the CLI's ``summary.json`` (the EN 50318 statistics
    per pantograph in ``summary["pantographs"][i]["stats"]``, forces in N, lengths in mm where
    the key says so). ``timeseries``: a dict of numpy arrays keyed as the columns of
    ``timeseries.csv`` (``time_s``, ``<pantograph>_position_m``, ``_force_n``,
    ``_force_filtered_n``, ``_height_m``, and with lateral motion ``_lateral_m``,
    ``_head_margin_m``). Picklable (plain data), so it crosses to and from Dask workers.
    """

    __slots__ = ("summary", "timeseries")

    def __init__(self, summary: Dict[str, Any], timeseries: Dict[str, np.ndarray]):
        self.summary = summary
        self.timeseries = timeseries

    @classmethod
    def _from_native(cls, handed: Tuple[str, List[Tuple[str, np.ndarray]], Optional[str]]) -> "Result":
        """The result, or ``RunEventError`` (with the result attached) when the run had an
        error-level event that was not accepted."""
        summary_json, columns, refused = handed
        result = cls(json.loads(summary_json), dict(columns))
        if refused is not None:
            raise RunEventError(refused, result)
        return result

    @property
    def errors(self) -> List[str]:
        """The run's error-level events (``summary.json``'s ``errors``): a dewirement, contact
        lost over 10 % of the analysis section. Empty for a run without one."""
        return list(self.summary.get("errors", []))

    def __getstate__(self):
        return (self.summary, self.timeseries)

    def __setstate__(self, state):
        self.summary, self.timeseries = state

    def __repr__(self) -> str:
        return "Result({!r}, {} km/h, {} steps)".format(
            self.summary.get("case_name"),
            self.summary.get("speed_kmh"),
            len(self.timeseries.get("time_s", [])),
        )


def run(case: Case, threads: int = 1, allow_dewirement: bool = False,
        allow_contact_loss: bool = False, verify: bool = False, sensitivity: bool = False,
        sensitivity_samples: Optional[int] = None, sensitivity_seed: Optional[int] = None,
        sensitivity_max_runs: Optional[int] = None, allow_failed_runs: bool = False) -> Result:
    """Simulate one case (the interpreter released) and take its statistics.

    ``threads``: the run's threads, as the CLI's ``run --threads`` (a line of several tension
    lengths splits its work between them; capped at the machine's cores; the same numbers on any
    count). ``sweep`` runs one case per thread instead. A run with an error-level event (a
    dewirement, contact lost over 10 % of the analysis section) raises ``RunEventError`` with
    the result attached, unless ``allow_dewirement`` or ``allow_contact_loss`` accepts it (the
    CLI's ``--allow-dewirement``, ``--allow-contact-loss``). ``verify``: the case run again
    refined (twice the modes, half the time step) and with the contact twice as stiff, as the
    CLI's ``--verify``: ``summary["verification"]`` holds each statistic beside both, and
    ``summary["verification"]["not_converged"]`` those not converged to their tolerance.
    ``sensitivity``: every value the case's text gives a range run at its low and its high end,
    then ``sensitivity_samples`` runs (8) with all drawn at once from ``sensitivity_seed`` (1), as
    the CLI's ``--sensitivity``: ``summary["sensitivity"]`` holds each statistic's band and the
    values that move it most. The ranges come from ``Case.preset``, ``from_toml`` and
    ``from_file``; a path set by ``with_overrides`` is not varied; a pickled case carries none.
    A study of more than ``sensitivity_max_runs`` runs (200) is refused before any run; one with
    runs that could not be made, or with events not accepted, raises ``ValueError`` with the
    count and the first reason, unless ``allow_failed_runs`` (the CLI's ``--allow-failed-runs``)."""
    return Result._from_native(_pcsim.run(case, threads, allow_dewirement, allow_contact_loss,
                                          verify, sensitivity, sensitivity_samples,
                                          sensitivity_seed, sensitivity_max_runs,
                                          allow_failed_runs))


def sweep(cases: Sequence[Case], client: Any = None, jobs: Optional[int] = None,
          allow_dewirement: bool = False, allow_contact_loss: bool = False) -> List[Result]:
    """Run many cases and return their results in case order.

    Without ``client``: a local thread pool of ``jobs`` threads (all cores by default). With a
    ``dask.distributed.Client``: the cases are mapped over its workers, each case
    single-threaded on its worker; the numbers are the same as a local run's and the CLI's (the
    runs are deterministic). A case with an error-level event raises ``RunEventError`` as
    ``run`` does, unless the ``allow_`` flags accept it."""
    cases = list(cases)
    if client is None:
        handed = _pcsim.run_many(cases, jobs, allow_dewirement, allow_contact_loss)
        return [Result._from_native(h) for h in handed]
    futures = client.map(run, cases, allow_dewirement=allow_dewirement,
                         allow_contact_loss=allow_contact_loss, pure=False)
    return client.gather(futures)


def eva(
    case: Case,
    speeds_kmh: Sequence[float],
    tensions_n: Sequence[float],
    step_m: float = 1.0,
    tolerance_j: float = 0.01,
    fraction: float = 0.99,
    jobs: Optional[int] = None,
    seeds: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
    max_steps: Optional[int] = None,
    max_memory_gb: Optional[float] = None,
) -> List[Dict[str, Any]]:
    """Energy distribution and EVA length over speeds (km/h) × contact-wire tensions (N): one
    dict per case with the columns of the CLI's ``eva.csv`` (lengths in m, energies in J; None
    where a criterion was not reached). The core's one sweep, as ``pcsim eva``: ``seeds``
    realisations of the case's random inputs, a ``shard`` ``(index, count)``, and the resource
    budget of ``--max-steps`` and ``--max-memory-gb``."""
    return json.loads(
        _pcsim.eva(case, list(speeds_kmh), list(tensions_n), step_m, tolerance_j, fraction, jobs,
                   seeds, shard, max_steps, max_memory_gb)
    )


def window(
    case: Case,
    speeds_kmh: Sequence[float],
    tensions_n: Sequence[float],
    mean_tol_pct: float = 1.0,
    sigma_tol_pct: float = 3.0,
    max_tol_pct: float = 5.0,
    min_window_m: Optional[float] = None,
    max_window_m: float = 400.0,
    coarse_m: float = 20.0,
    resolution_m: float = 1.0,
    jobs: Optional[int] = None,
    seeds: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
    max_steps: Optional[int] = None,
    max_memory_gb: Optional[float] = None,
    coarse_only: bool = False,
    pantograph: Optional[str] = None,
) -> List[Dict[str, Any]]:
    """The accuracy-based real-time window length over speeds (km/h) × tensions (N): one dict
    per case with the columns of ``pcsim window``'s ``window.csv``, by the same core sweep. As
    the CLI, every window at ``resolution_m`` from ``max_window_m`` down to the first that fails
    is run, so the length is the shortest with every longer window matching; ``coarse_only``
    gives the quick lattice answer (``--coarse-only``). ``pantograph`` is the one the window
    follows (``--pantograph``: leading, trailing, a name or an index)."""
    return json.loads(
        _pcsim.window(case, list(speeds_kmh), list(tensions_n), mean_tol_pct, sigma_tol_pct,
                      max_tol_pct, min_window_m, max_window_m, coarse_m, resolution_m, jobs, seeds,
                      shard, max_steps, max_memory_gb, not coarse_only, pantograph)
    )


def validate(
    name: str = "en50318-2002",
    jobs: Optional[int] = None,
    case: Optional[Any] = None,
    targets: Optional[Any] = None,
    verify: bool = False,
) -> Dict[str, Any]:
    """A validation (``en50318-2002`` or ``seed-table1``): the report of ``pcsim validate
    --json`` (value against range per row, with its unit). ``targets`` (a file's path or its
    TOML text) gives a user's ranges instead of ``name``'s, as ``--targets``; ``case`` (a
    :class:`Case`, or a case file's path) runs instead of the preset the targets name, as
    ``pcsim validate CASE.toml``. ``verify``: each run again refined and with the contact twice
    as stiff, as ``--verify``: every row gains ``verification`` and the report
    ``not_established``."""
    case_label = None
    if case is not None and not isinstance(case, Case):
        case_label = os.fspath(case)
        case = Case.from_file(case_label)
    elif case is not None:
        case_label = "Case"
    targets_text, targets_label = None, None
    if targets is not None:
        if name != "en50318-2002":
            raise ValueError(
                "validate: give a validation name ({!r}) or targets, not both".format(name)
            )
        targets_text, path = _text_or_path(targets, "targets")
        targets_label = path or "targets"
    return json.loads(
        _pcsim.validate(name, jobs, case, case_label, targets_text, targets_label, verify)
    )


def _text_or_path(value: Any, what: str) -> Tuple[str, Optional[str]]:
    """``(text, path)`` of an argument that is a file's path or its TOML text: a path object is
    always a path; a string with a line break is text; a one-line string is a path when no
    ``=`` in it makes it TOML. A path that does not exist raises ``FileNotFoundError`` naming the
    argument (it is never parsed as TOML text)."""
    import os

    if isinstance(value, os.PathLike) or (
        isinstance(value, str) and "\n" not in value and "=" not in value
    ):
        path = os.fspath(value)
        if not os.path.isfile(path):
            raise FileNotFoundError(
                "{}: no such file: {!r} (give the path of an existing file, or the TOML text "
                "itself)".format(what, path)
            )
        with open(path, encoding="utf-8") as f:
            return f.read(), path
    if not isinstance(value, str):
        raise TypeError("{}: a path or TOML text, not {}".format(what, type(value).__name__))
    return value, None


def study(spec: Any) -> Dict[str, Any]:
    """A study written as a spec file, its ``kind`` naming it (``"wear"``: current collection),
    run by the core's table as ``pcsim study`` runs it: ``spec`` is the file's path or its TOML
    text (its ``case`` a preset's name or a file beside the spec). Returns ``kind``, ``answer``
    (headline, rows, warnings, failures), ``files`` (each file's text, as the CLI writes them)
    and ``output`` (the typed ``KIND.json`` parsed). An answer with failures (error-level events
    not accepted) raises ``ValueError`` naming the first, as the CLI exits with status 2."""
    import os

    text, path = _text_or_path(spec, "spec")
    base = os.path.dirname(os.path.abspath(path)) if path else "."
    kind, answer, files = _pcsim.study(text, base)
    files = dict(files)
    answer = json.loads(answer)
    out = {
        "kind": kind,
        "answer": answer,
        "files": files,
        "output": json.loads(files["{}.json".format(kind)]) if "{}.json".format(kind) in files else None,
    }
    if answer["failures"]:
        raise ValueError("the {} study is refused: {}".format(kind, answer["failures"][0]))
    return out


def assess(result: "Result", system: Optional[str] = None, criteria: Any = None) -> Dict[str, Any]:
    """A run against the acceptance criteria (EN 50367, TSI Energy, EN 50119): the assessment of
    ``pcsim assess`` as a dict (``rows``: value, limit, verdict, clause and source per criterion
    and pantograph). ``system``: ``"ac"``, ``"dc-3kv"`` or ``"dc-1.5kv"`` (without it the
    criteria that depend on it are listed in ``skipped``); ``criteria``: your own criteria as TOML
    text (status ``"user"``, each with its source). A criterion whose limit pcsim cannot cite
    gives the value and the verdict ``"no-limit"``; ``criteria`` may also be the path of such a
    file (a path that does not exist raises ``FileNotFoundError``). The run's error-level events
    are in ``run_errors``; with any, the run is not accepted. ``result`` may also be what
    ``pcsim.study`` returned for the current-collection study (``kind`` ``"wear"``): its arcing
    (NQ per train and pantograph) is assessed, as ``pcsim assess`` does on its directory."""
    if criteria is not None:
        criteria, _ = _text_or_path(criteria, "criteria")
    if isinstance(result, dict) and result.get("kind") == "wear":
        text, kind = result["files"]["wear.json"], "wear"
    else:
        text, kind = json.dumps(result.summary), "run"
    return json.loads(_pcsim.assess(text, kind, system, criteria))


def pantograph_frf(case: Case, pantograph: Optional[str] = None, quantity: str = "apparent-mass",
                   from_hz: float = 0.1, to_hz: float = 20.0, points: int = 200) -> Dict[str, Any]:
    """The frequency response at the head of the case's pantograph (``pcsim pantograph frf``):
    ``{"frequency_hz", "magnitude", "phase_deg", "unit"}`` with NumPy arrays; ``quantity``:
    ``"apparent-mass"`` (kg) or ``"receptance"`` (m/N); ``pantograph``: leading, trailing, a name
    or an index."""
    f, m, p, unit = _pcsim.pantograph_frf(case, pantograph, quantity, from_hz, to_hz, points)
    return {"frequency_hz": np.asarray(f), "magnitude": np.asarray(m),
            "phase_deg": np.asarray(p), "unit": unit}


def pantograph_fit(measured: Any, case: Case, pantograph: Optional[str] = None,
                   starts: Optional[int] = None, seed: Optional[int] = None,
                   max_residual_percent: Optional[float] = None) -> Dict[str, Any]:
    """The case's pantograph fitted to a measured response (``pcsim pantograph fit``):
    ``measured`` is the CSV's path or text (``frequency_hz``, ``magnitude_kg`` or
    ``magnitude_m_per_n``, ``phase_deg``). The dict of ``fit.json`` (each value with its
    uncertainty, the residual) and ``case_block``, the ``[[pantographs]]`` block with the
    measurement as its source. ``starts``, ``seed`` and ``max_residual_percent`` are the CLI's
    flags (``None``: the core's defaults); a fit whose residual is above
    ``max_residual_percent`` raises ``ValueError`` with the reason (the CLI's exit status 1)."""
    if isinstance(measured, os.PathLike) or (isinstance(measured, str) and "\n" not in measured):
        path = os.fspath(measured)
        if not os.path.isfile(path):
            raise FileNotFoundError("measured: no such file: {!r}".format(path))
        with open(path, encoding="utf-8") as f:
            text, label = f.read(), os.path.basename(path)
    else:
        text, label = measured, "measured"
    fit_json, block = _pcsim.pantograph_fit(text, label, case, pantograph, starts, seed,
                                            max_residual_percent)
    out = json.loads(fit_json)
    out["case_block"] = block
    return out


def _design_evaluate(spec_toml: str, base_dir: str, x: List[float]) -> List[str]:
    """One design's journal row (runs on a Dask worker; module level, so it pickles by name)."""
    return list(_pcsim.design_evaluate(spec_toml, base_dir, list(x)))


def design(
    spec: Any,
    client: Any = None,
    jobs: Optional[int] = None,
    journal: Any = None,
) -> Dict[str, Any]:
    """The design search of ``pcsim design SPEC.toml``: the same spec, the same answer (the
    content of its ``design.json``: ``best``, ``sensitivity``, ``constraints``, ``feasible``…).

    ``spec``: a path to the spec (its ``base.file`` is read relative to it) or its TOML text
    (``base.file`` relative to the working directory); a path that does not exist raises
    ``FileNotFoundError``. ``journal``: a path to a journal
    (design.csv's format, the CLI's): resumed when it exists (its evaluations are not run again),
    appended to batch by batch, so an interrupted search continues where it stopped. ``client``:
    a ``dask.distributed.Client``: each batch's designs are evaluated on its workers (one design
    per task, single-threaded), with the numbers of a local run. Without it, ``jobs`` threads
    here (all cores by default)."""
    import csv
    import io
    import os

    text, path = _text_or_path(spec, "spec")
    base_dir = os.getcwd() if path is None else os.path.dirname(os.path.abspath(path))
    rows: List[List[str]] = []
    if journal is not None and os.path.exists(journal):
        with open(journal, encoding="utf-8", newline="") as f:
            content = f.read()
        if content and not content.endswith("\n"):
            # A row torn by a kill: dropped, as the CLI does.
            content = content[: content.rfind("\n") + 1]
            with open(journal, "w", encoding="utf-8", newline="") as f:
                f.write(content)
        rows = [r for r in csv.reader(io.StringIO(content))]
    if journal is not None and not rows:
        with open(journal, "w", encoding="utf-8", newline="") as f:
            csv.writer(f, lineterminator="\n").writerow(_pcsim.design_header(text, base_dir))

    def on_batch(new_rows: List[List[str]]) -> None:
        if journal is not None:
            with open(journal, "a", encoding="utf-8", newline="") as f:
                csv.writer(f, lineterminator="\n").writerows(new_rows)
                f.flush()
                os.fsync(f.fileno())

    evaluate = None
    if client is not None:
        def evaluate(xs: List[List[float]]) -> List[List[str]]:
            futures = client.map(_design_evaluate, [text] * len(xs), [base_dir] * len(xs), xs,
                                 pure=False)
            return client.gather(futures)

    answer, _header = _pcsim.design(text, base_dir, rows, on_batch, evaluate, jobs)
    return json.loads(answer)


def presets() -> List[str]:
    """The names of the embedded presets."""
    return list(_pcsim.presets_list())
