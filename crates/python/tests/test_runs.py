"""The runner from Python against the CLI: `run()` on the quick pipeline
gives the CLI's products file for file, `load()` reads a run back, and every
stage kind called through the Python bridge, replayed in pipeline order on
the products of the Python replay itself, gives the CLI's products byte for
byte (tables as the Parquet bytes the runner writes, fields bit for bit with
their spacing, files byte for byte)."""

import json
from pathlib import Path

import numpy as np
import polars as pl
import pytest

import hypercontact
from hypercontact import _hypercontact

from conftest import GUARD, QUICK


def _hashes(run_dir: Path):
    record = json.loads((run_dir / "provenance.json").read_text())
    return {name: s["outputs"] for name, s in record["stages"].items()}


def test_run_equals_the_cli_run(cli_quick, tmp_path):
    run = hypercontact.run(QUICK, out=tmp_path / "out", cache=tmp_path / "cache", progress=False)
    assert run.computed == len(run.provenance["stages"]) and run.cached == 0
    assert _hashes(run.out_dir) == _hashes(cli_quick)
    # The cache is the CLI's: a second run, by either, computes nothing.
    again = hypercontact.run(QUICK, out=tmp_path / "out", cache=tmp_path / "cache", progress=False)
    assert again.computed == 0 and again.cached > 0
    assert "cached" in again.summary


def test_load_reads_every_exported_product(cli_quick):
    run = hypercontact.load(cli_quick)
    response = run["t1-bem.response"]
    assert isinstance(response, pl.DataFrame) and response.height > 10
    assert response["load_n"][0] == 0.0
    height = run["t1-patch.height"]
    assert isinstance(height, hypercontact.Field) and height.shape == (32, 32)
    assert np.array_equal(height.heights_m, np.load(cli_quick / "t1-patch" / "height.npy"))
    maps = run["t1-bem.contact_maps"]
    assert maps.index is not None and len(maps) == 2 * maps.index.height
    assert all(path.is_file() for path in maps.values())
    with pytest.raises(KeyError, match="stage.output"):
        run["t1-bem.nothing"]
    with pytest.raises(ValueError, match="provenance.json"):
        hypercontact.load(cli_quick / "t1-bem")


def _replay_order(stages, record):
    """Pipeline stages in an order where every input is made before it is
    read (the CLI's provenance names where each input came from)."""
    done, order = set(), []
    pending = list(stages)
    while pending:
        ready = [s for s in pending
                 if all(i["from"].split(".")[0] in done
                        for i in record["stages"][s[0]]["inputs"].values())]
        assert ready, f"no stage ready among {[s[0] for s in pending]}"
        for s in ready:
            order.append(s)
            done.add(s[0])
            pending.remove(s)
    return order


def _assert_same_product(cli_dir: Path, stage: str, output: str, product, kind: str):
    tag = product[0]
    if tag == "table":
        assert product[1] == (cli_dir / f"{output}.parquet").read_bytes(), f"{stage}.{output}"
    elif tag == "field":
        cli = np.load(cli_dir / f"{output}.npy")
        grid = json.loads((cli_dir / f"{output}.grid.json").read_text())
        values = np.asarray(product[1])
        assert values.tobytes() == cli.tobytes() and values.shape == cli.shape, f"{stage}.{output}"
        assert (product[2], product[3]) == (grid["dx_m"], grid["dy_m"]), f"{stage}.{output}"
    else:
        files, index = product[1], product[2]
        for name, data in files.items():
            if kind == "report" and name == "index.html":
                # The page prints the run's provenance, which only the runner
                # hands a stage; a lone call has none. Its figures and tables
                # are compared like every other file.
                continue
            assert data == (cli_dir / name).read_bytes(), f"{stage}.{output}: {name}"
        if index is not None:
            assert index == (cli_dir / f"{output}.parquet").read_bytes(), f"{stage}.{output} index"


@pytest.mark.parametrize("pipeline", [GUARD, QUICK], ids=["guard", "quick"])
def test_every_stage_from_python_gives_the_cli_products(cli_run, pipeline):
    cli_dir = cli_run(pipeline)
    record = json.loads((cli_dir / "provenance.json").read_text())
    base_dir, stages = _hypercontact.pipeline_stages(str(pipeline))
    products = {}
    kinds_seen = set()
    for name, kind, params_json in _replay_order(stages, record):
        inputs = {input_name: products[i["from"]]
                  for input_name, i in record["stages"][name]["inputs"].items()}
        outputs, _notes = _hypercontact.run_stage(kind, inputs, params_json, False, base_dir)
        for output, product in outputs.items():
            products[f"{name}.{output}"] = product
        if record["stages"][name].get("temp"):
            continue  # not exported: checked through the stages that read it
        kinds_seen.add(kind)
        for output, product in outputs.items():
            _assert_same_product(cli_dir / name, name, output, product, kind)
    # Every kind the quick pipeline uses was compared, directly or (a
    # temporary stage's) through the products of the stages that read it.
    used = {kind for _, kind, _ in stages}
    temporary = {s["kind"] for s in record["stages"].values() if s.get("temp")}
    assert used - kinds_seen <= temporary, used - kinds_seen
    if pipeline == GUARD:
        assert kinds_seen == {k.kind for k in hypercontact.kinds()}


def test_a_bad_set_raises_the_cli_message(tmp_path):
    with pytest.raises(ValueError, match=r"no stage `nope`"):
        hypercontact.run(QUICK, out=tmp_path / "o", cache=tmp_path / "c", set={"nope.steps": 3})
    with pytest.raises(ValueError, match=r"parameter `steps`"):
        hypercontact.run(QUICK, out=tmp_path / "o", cache=tmp_path / "c", set={"t1-bem.steps": 0})


def test_study_gathers_the_collected_tables_like_the_cli(tmp_path):
    demo = QUICK.parent / "demo.yaml"
    from conftest import run_cli
    run_cli("study", demo, "--out", tmp_path / "cli", "--cache", tmp_path / "cache", "--quiet")
    study = hypercontact.study(demo, out=tmp_path / "py", cache=tmp_path / "cache", progress=False)
    assert len(study.variants) == 4
    gathered = study.tables["contact.response"]
    assert gathered.equals(pl.read_parquet(tmp_path / "cli" / "contact.response.parquet"))
    values, variant = study.variants[0]
    assert set(values) == {"contact.scheme", "trunc.levels"}
    assert variant["contact.response"].height > 0
