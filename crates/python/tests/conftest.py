"""Shared fixtures of the Python suite: the repository, the CLI binary the
Rust build made (`cargo test --workspace --release` builds it), and one CLI
run of the quick pipeline that several tests compare against."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
QUICK = REPO / "pipelines" / "quick.yaml"
# The version guard's fixture: every stage kind, none temporary, in seconds.
GUARD = REPO / "tests" / "guard" / "pipeline.yaml"


def cli_binary() -> Path:
    binary = Path(os.environ.get("HYPERCONTACT_BIN", REPO / "target" / "release" / "hypercontact"))
    if not binary.is_file():
        pytest.fail(f"{binary}: no CLI binary; build it with `cargo build --release` "
                    "or point HYPERCONTACT_BIN at one")
    return binary


def run_cli(*args, cwd=None) -> subprocess.CompletedProcess:
    done = subprocess.run([str(cli_binary()), *map(str, args)], cwd=cwd,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="session")
def cli_run(tmp_path_factory):
    """A pipeline run by the CLI into a fresh folder and cache, once per
    session: `cli_run(path)` gives its run folder."""
    done = {}

    def run(pipeline: Path) -> Path:
        if pipeline not in done:
            root = tmp_path_factory.mktemp("cli-" + pipeline.stem)
            run_cli("run", pipeline, "--out", root / "out", "--cache", root / "cache", "--quiet")
            done[pipeline] = root / "out"
        return done[pipeline]

    return run


@pytest.fixture(scope="session")
def cli_quick(cli_run) -> Path:
    return cli_run(QUICK)
