"""A stage from Python costs what it costs in the CLI: a 512 x 512 BEM curve,
timed as the best of seven in each, the two taking turns so that a busy
moment of the machine falls on both (the CLI's own stage time from its
provenance; from Python the whole call, conversions and file outputs
included). Measured on the 2-core build machine, 2026-11-27: CLI 2.51-2.73 s,
Python 2.58-2.91 s, best over best 1.02-1.06."""

import json
import time

import hypercontact
from conftest import run_cli

PIPELINE = """name: bem512
stages:
  surf:
    uses: synth-surface
    with: {{ tile_px: 512, tiles_x: 1, tiles_y: 1, seed: 7 }}
  epdm:
    uses: material-preset
  bem:
    uses: bem
    inputs: {{ surface: surf.truth, material: epdm }}
    with: {BEM}
"""
BEM = dict(boundary="free", steps=6, max_area_fraction=0.3, map_fractions=[0.3])
REPEATS = 7


def test_a_512_bem_from_python_takes_the_cli_time(tmp_path):
    pipeline = tmp_path / "bem512.yaml"
    pipeline.write_text(PIPELINE.format(BEM=json.dumps(BEM)))
    out, cache = tmp_path / "out", tmp_path / "cache"
    run_cli("run", pipeline, "--out", out, "--cache", cache, "--quiet")
    run = hypercontact.load(out)
    surface, material = run["surf.truth"], run["epdm.material"]
    assert surface.shape == (512, 512)
    cli_s, python_s = [], []
    for _ in range(REPEATS):
        started = time.perf_counter()
        result = hypercontact.stages.bem(surface=surface, material=material,
                                         out_dir=tmp_path / "maps", progress=False, **BEM)
        python_s.append(time.perf_counter() - started)
        run_cli("run", pipeline, "--out", out, "--cache", cache, "--quiet", "--force", "bem")
        record = json.loads((out / "provenance.json").read_text())
        cli_s.append(record["stages"]["bem"]["wall_s"])
    # The same curve, so the same work was timed.
    assert result["response"].equals(run["bem.response"])
    print(f"512² bem: CLI {sorted(cli_s)} s, Python {sorted(python_s)} s")
    assert min(python_s) <= 1.05 * min(cli_s), (cli_s, python_s)
