"""`pcsim schema` (issue 52): the case file's JSON Schema validates every shipped preset and
example case, a misspelt key or a wrong type fails it, and a run's summary.json, a Monte Carlo
study's montecarlo.json, an assessment's assessment.json, a design's design.json, a fit's
fit.json, a comparison's compare.json and each directory's pcsim.json validate against their schemas (and a wrong value fails each). The validator is an independent tool
(python-jsonschema, from PyPI); TOML is read by Python's own tomllib.

Run by .ci/run: PCSIM=target/release/pcsim target/py-venv/bin/python -m pytest -q tests/schema
"""

import json
import os
import pathlib
import subprocess
import tomllib

import jsonschema
import pytest

PCSIM = os.environ.get("PCSIM", "pcsim")
ROOT = pathlib.Path(__file__).resolve().parents[2]


def schema(name):
    out = subprocess.run([PCSIM, "schema", name], check=True, capture_output=True, text=True)
    s = json.loads(out.stdout)
    jsonschema.validators.validator_for(s).check_schema(s)
    return s


def validator(name):
    s = schema(name)
    return jsonschema.validators.validator_for(s)(s)


def shipped_cases():
    files = sorted(ROOT.glob("presets/*.toml")) + sorted(ROOT.glob("examples/**/*.toml"))
    return [f for f in files if "[catenary]" in f.read_text(encoding="utf-8")]


CASE_FILES = shipped_cases()


def test_every_preset_and_example_is_found():
    presets = subprocess.run([PCSIM, "presets"], check=True, capture_output=True, text=True)
    names = [line.split()[0] for line in presets.stdout.splitlines() if line.strip()]
    shipped = {f.stem for f in CASE_FILES if f.parent.name == "presets"}
    assert set(names) == shipped, (names, shipped)
    assert len(CASE_FILES) > len(names)  # the examples too


@pytest.mark.parametrize("path", CASE_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_case_validates(path):
    validator("case").validate(tomllib.loads(path.read_text(encoding="utf-8")))


def preset_text():
    return (ROOT / "presets" / "en50318-2002.toml").read_text(encoding="utf-8")


def errors(case_text):
    return list(validator("case").iter_errors(tomllib.loads(case_text)))


def test_a_misspelt_key_fails_the_schema_and_pcsim(tmp_path):
    text = preset_text()
    assert not errors(text)
    for good, bad in [("tension_n", "tensoin_n"), ("[catenary.droppers]", "[catenary.dropers]"),
                      ("source =", "sorce =")]:
        wrong = text.replace(good, bad, 1)
        assert wrong != text
        assert errors(wrong), f"{bad} passed the schema"
        # pcsim refuses the same file, by the key.
        f = tmp_path / "wrong.toml"
        f.write_text(wrong, encoding="utf-8")
        r = subprocess.run([PCSIM, "run", str(f), "--quiet", "--out", str(tmp_path / "o")],
                           capture_output=True, text=True)
        assert r.returncode != 0
        assert bad.strip("[]= ").split(".")[-1] in r.stderr, r.stderr


def test_a_wrong_type_fails_the_schema():
    text = preset_text()
    wrong = text.replace("[run]", "[run]\nspeed_kmh_typo_free = 1", 1)
    assert errors(wrong)
    import re
    wrong = re.sub(r"speed_kmh = [^\n]*", 'speed_kmh = "fast"', text, count=1)
    assert wrong != text
    assert errors(wrong)


def short_case_text():
    """en50318-2002 on 8 spans, its pantograph over the middle (the Python package's own case,
    as TOML), with 2 mm of seeded irregularity (a random input for Monte Carlo)."""
    import pcsim
    case = pcsim.Case.preset("en50318-2002").with_overrides(
        {"catenary.spans": 8, "run.start_m": 60.0, "run.end_m": 400.0,
         "run.analysis_m": [120.0, 360.0]})
    return case.to_toml() + """
[[irregularity]]
kind = "psd"
rms_m = 0.002
min_wavelength_m = 2.0
max_wavelength_m = 60.0
exponent = 2.0
seed = 7
"""


def test_outputs_validate_against_their_schemas(tmp_path):
    f = tmp_path / "case.toml"
    f.write_text(short_case_text(), encoding="utf-8")
    validator("case").validate(tomllib.loads(f.read_text(encoding="utf-8")))
    r = subprocess.run([PCSIM, "run", str(f), "--quiet", "--out", str(tmp_path / "run")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    validator("summary").validate(summary)
    broken = dict(summary, pantographs="none")
    with pytest.raises(jsonschema.ValidationError):
        validator("summary").validate(broken)
    r = subprocess.run([PCSIM, "run", str(f), "--seeds", "2", "--quiet", "--out",
                        str(tmp_path / "mc")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    mc = json.loads((tmp_path / "mc" / "montecarlo.json").read_text())
    validator("montecarlo").validate(mc)
    with pytest.raises(jsonschema.ValidationError):
        validator("montecarlo").validate({})


def test_assessment_design_and_fit_validate_against_their_schemas(tmp_path):
    f = tmp_path / "case.toml"
    f.write_text(short_case_text(), encoding="utf-8")
    run = tmp_path / "run"
    r = subprocess.run([PCSIM, "run", str(f), "--quiet", "--out", str(run)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([PCSIM, "assess", str(run), "--system", "ac"],
                       capture_output=True, text=True)
    assert r.returncode in (0, 1), r.stderr
    a = json.loads((run / "assessment.json").read_text())
    validator("assessment").validate(a)
    with pytest.raises(jsonschema.ValidationError):
        validator("assessment").validate(dict(a, rows=[dict(a["rows"][0], verdict="fine")]))

    ex = ROOT / "examples" / "pantograph"
    r = subprocess.run([PCSIM, "pantograph", "fit", str(ex / "measured-apparent-mass.csv"),
                        str(ex / "start-25-percent-off.toml"), "--quiet", "--out",
                        str(tmp_path / "fit")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    fit = json.loads((tmp_path / "fit" / "fit.json").read_text())
    validator("fit").validate(fit)
    with pytest.raises(jsonschema.ValidationError):
        validator("fit").validate(dict(fit, residual_rms="small"))

    spec = tmp_path / "spec.toml"
    spec.write_text((ROOT / "tests" / "design" / "swarm.toml").read_text(encoding="utf-8"),
                    encoding="utf-8")
    r = subprocess.run([PCSIM, "design", str(spec), "--quiet", "--no-plot", "--out",
                        str(tmp_path / "design")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    d = json.loads((tmp_path / "design" / "design.json").read_text())
    validator("design").validate(d)
    with pytest.raises(jsonschema.ValidationError):
        validator("design").validate(dict(d, stop="bored"))

    b55 = tmp_path / "b55"
    r = subprocess.run([PCSIM, "run", "--preset", "benchmark-55m", "--quiet", "--out", str(b55)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([PCSIM, "compare", str(b55), str(ROOT / "examples" / "compare" / "measured.csv"),
                        "--search", "30m", "--no-plot", "--out", str(tmp_path / "compare")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    c = json.loads((tmp_path / "compare" / "compare.json").read_text())
    validator("compare").validate(c)
    with pytest.raises(jsonschema.ValidationError):
        validator("compare").validate(dict(c, comparison=dict(c["comparison"], shift_samples=0.5)))

    r = subprocess.run([PCSIM, "realtime", "--preset", "benchmark-55m", "--window", "165",
                        "--no-plot", "--quiet", "--out", str(tmp_path / "realtime")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    rt = json.loads((tmp_path / "realtime" / "realtime.json").read_text())
    validator("realtime").validate(rt)
    assert rt["windows"][0]["window_m"] == 165
    with pytest.raises(jsonschema.ValidationError):
        validator("realtime").validate(dict(rt, windows=[dict(rt["windows"][0], modes=-1)]))

    # Each directory's manifest, complete, with its files and their hashes.
    for out in ["run", "fit", "design", "compare", "realtime"]:
        m = json.loads((tmp_path / out / "pcsim.json").read_text())
        assert m["complete"] is True and m["files"], m
        validator("manifest").validate(m)
    with pytest.raises(jsonschema.ValidationError):
        validator("manifest").validate(dict(m, shard="x"))


def test_a_wear_spec_and_its_outputs_validate_against_their_schemas(tmp_path):
    # Issue 54: the shipped wear spec validates against `pcsim schema wear-spec` and a misspelt
    # key fails it (and pcsim, naming it); a wear study's wear.json, answer.json and
    # figures.json validate against `wear`, `answer` and `figures`, and a wrong value fails.
    spec_file = ROOT / "presets" / "studies" / "wear-2018-like.toml"
    text = spec_file.read_text(encoding="utf-8")
    v = validator("wear-spec")
    v.validate(tomllib.loads(text))
    bad = text.replace("bin_m =", "bin_mm =")
    assert list(v.iter_errors(tomllib.loads(bad)))
    (tmp_path / "bad.toml").write_text(bad)
    r = subprocess.run([PCSIM, "study", str(tmp_path / "bad.toml"), "--no-plot"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "bin_mm" in r.stderr, r.stderr
    second = [i for i in range(len(text)) if text.startswith("[[trains]]", i)][1]
    one = text[:second] + text[text.index("[law]"):]
    (tmp_path / "spec.toml").write_text(one)
    out = tmp_path / "out"
    subprocess.run([PCSIM, "study", str(tmp_path / "spec.toml"), "--quiet", "--out", str(out)],
                   check=True, capture_output=True)
    wear = json.loads((out / "wear.json").read_text())
    validator("wear").validate(wear)
    validator("answer").validate(json.loads((out / "answer.json").read_text()))
    validator("figures").validate(json.loads((out / "figures.json").read_text()))
    wear["trains"][0]["pantographs"][0]["nq_percent"] = "none"
    assert list(validator("wear").iter_errors(wear))
    # A pantograph's response through the contract (issue 52): frf.json against `frf`.
    frf = tmp_path / "frf"
    subprocess.run([PCSIM, "pantograph", "frf", "--preset", "en50318-2002", "--points", "20",
                    "--quiet", "--out", str(frf)], check=True, capture_output=True)
    doc = json.loads((frf / "frf.json").read_text())
    validator("frf").validate(doc)
    validator("answer").validate(json.loads((frf / "answer.json").read_text()))
    doc["magnitude"] = "big"
    assert list(validator("frf").iter_errors(doc))
