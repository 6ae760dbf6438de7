"""The command line's outputs: every JSON output valid against its schema (docs/schemas),
and trajectory.csv and sweep.csv as pandas reads them (units in the column names, keys that
compare equal to the decimals typed)."""

import json
from pathlib import Path

import jsonschema
import pandas as pd
import pytest

SCHEMAS = Path(__file__).resolve().parents[2] / "docs" / "schemas"
QUICK = ["--horizon", "10", "--step", "0.1", "--target", "0.01,0.01,0"]


def valid(schema, instance):
    """Validates `instance` (a path to a JSON file, or the text) against docs/schemas/`schema`."""
    text = instance.read_text() if isinstance(instance, Path) else instance
    spec = json.loads((SCHEMAS / f"{schema}.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(spec)
    jsonschema.validate(json.loads(text), spec, cls=jsonschema.Draft202012Validator)


@pytest.fixture(scope="module")
def solved(cli, tmp_path_factory):
    """A quick solve on a joint limit it touches, with figures (its manifest lists them)."""
    out = tmp_path_factory.mktemp("solve") / "out"
    cli("solve", *QUICK, "--starts", "8", "--alpha-max", "60deg", "-q", "--out", out)
    return out


def test_solve_outputs_match_their_schemas(solved, cli, tmp_path):
    valid("solve-report", solved / "report.json")
    valid("costate", solved / "costate.json")
    valid("manifest", solved / "purcell-sim-manifest.json")
    cli("replay", "--costate", solved / "costate.json", "--out", tmp_path / "replay.json")
    valid("replay-report", tmp_path / "replay.json")
    with pytest.raises(jsonschema.ValidationError):
        valid(
            "solve-report",
            (solved / "report.json").read_text().replace('"version": 1', '"version": 2'),
        )


def test_old_costate_files_match_the_schema(cli, tmp_path):
    """A version-2 costate file (no joint limit) is still read, and its schema says so."""
    v2 = tmp_path / "v2.json"
    v2.write_text(
        json.dumps(
            {
                "format": "purcell-costate",
                "version": 2,
                "model": {"links": [1, 1, 1], "drag": 1, "ratio": 2},
                "h": 0.01,
                "steps": 200,
                "alpha0": [0, 0],
                "target": [0.1, 0.1, 0],
                "mu": [0.1, 0.2, 0.0],
                "xi0": [0.01, -0.02],
                "checkpoint_every": 100,
                "checkpoints": [
                    {"k": 100, "alpha": [0.01, -0.02], "g": [0.001, 0.0, 1, 0], "xi": [0.01, -0.02]}
                ],
            }
        )
    )
    valid("costate", v2)
    cli("replay", "--costate", v2)


def test_other_outputs_match_their_schemas(cli, tmp_path):
    valid("connection", cli("connection", "--alpha", "30deg,-20deg").stdout)
    printed = cli("field", "--out", tmp_path / "field").stdout
    valid("field", printed)
    valid("manifest", tmp_path / "field" / "purcell-sim-manifest.json")
    out = tmp_path / "sweep"
    cli(
        "sweep",
        "--x",
        "0:0.3:4",
        "--y",
        "0.05",
        *QUICK[:4],
        "--starts",
        "1",
        "--no-plots",
        "--out",
        out,
    )
    valid("sweep-report", out / "report.json")
    valid("manifest", out / "purcell-sim-manifest.json")
    frame = pd.read_csv(out / "sweep.csv")
    columns = "x_m,y_m,theta_rad,cost_rad2_per_s,residual,max_abs_alpha_rad,admissible,local_min,"
    assert list(frame.columns) == (columns + "kkt_residual_rad_per_s,status").split(",")
    # The grid keys are the decimals typed: 0.1, not 0.09999999999999999.
    assert list(frame.x_m) == [0.0, 0.1, 0.2, 0.3]
    assert (frame.x_m == 0.3).sum() == 1 and (frame.y_m == 0.05).all()


def test_robustness_report_matches_its_schema(cli):
    examples = SCHEMAS.parents[1] / "core" / "examples"
    for gait, source in (("paper-limit.gait", "lqr"), ("paper.gait", "extremal")):
        flags = ("--ratio-error", "0.1", "--json", "--plan")
        printed = cli("robustness", "--gait", examples / gait, *flags).stdout
        valid("robustness-report", printed)
        assert json.loads(printed)["design"]["feedforward"]["from"] == source


def test_trajectory_csv_loads_with_units_and_exact_times(solved):
    frame = pd.read_csv(solved / "trajectory.csv")
    columns = "k,t_s,alpha1_rad,alpha2_rad,u1_rad_per_s,u2_rad_per_s,x_m,y_m,theta_rad,"
    assert list(frame.columns) == (columns + "xi1_rad_per_s,xi2_rad_per_s,arc1,arc2").split(",")
    assert (frame.t_s == 9.9).sum() == 1 and (frame.t_s == 0.3).sum() == 1
    assert list(frame.k) == list(range(101))
    report = json.loads((solved / "report.json").read_text())
    assert report["arcs"], "the quick solve within 60 deg touches its limit"
    limit = report["problem"]["alpha_max"]
    flagged = 0
    for a in report["arcs"]:
        i, sign = a["joint"], a["sign"]
        rows = frame.iloc[a["first"] : a["last"] + 1]
        assert (rows[f"arc{i}"] == sign).all()
        assert ((rows[f"alpha{i}_rad"] * sign - limit).abs() < 1e-9).all()
        flagged += len(rows)
    assert (frame.arc1 != 0).sum() + (frame.arc2 != 0).sum() == flagged
