"""What `pip install` gives a user, away from this repository: the wheel is built (reusing the
CMake build folder, so only what changed compiles), installed into a new virtual environment in a
temporary folder, and its `vwg` command lists and runs a shipped world from there."""

from __future__ import annotations

import os
import subprocess
import sys
import venv

import pytest

from conftest import ROOT


def run(argv: list[str], cwd, timeout: float = 900) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    done = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
    assert done.returncode == 0, f"{argv}:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


@pytest.mark.slow
def test_the_wheel_runs_shipped_worlds_outside_the_repository(tmp_path):
    wheels = tmp_path / "wheels"
    run([sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-q", "-w", str(wheels),
         str(ROOT)], cwd=ROOT)
    (wheel,) = wheels.glob("vwg-*.whl")
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    run([str(python), "-m", "pip", "install", "-q", str(wheel)], cwd=tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    vwg = str(env_dir / "bin" / "vwg")
    listed = run([vwg, "worlds"], cwd=elsewhere).stdout
    for name in ("field", "maze", "office", "warehouse", "willow"):
        assert f"\n  {name} " in listed
    done = run([vwg, "run", "maze", "--goal", "dead_end_1_0", "--summary-json", "s.json"], cwd=elsewhere)
    assert "reached      yes" in done.stdout
    assert (elsewhere / "s.json").exists()
    # The package imports from the new environment, not from this repository.
    where = run([str(python), "-c", "import vwg; print(vwg.__file__)"], cwd=elsewhere).stdout
    assert str(env_dir) in where and str(ROOT) not in where
