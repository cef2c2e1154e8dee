"""The binary wheel (`make wheel`): installed into a new venv, it runs without the source tree and gives the
frames of the source build; its extension finds every library inside the wheel or among those the
manylinux policy lets a wheel expect of the system; its C++ SDK builds a downstream project that uses
the core and one that hosts Python, and refuses the components whose third-party headers it lacks.

The wheel is the one `make wheel` left in dist/ for this Python (`make wheel-test` makes it, then runs these);
without one the tests are skipped, saying so."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import venv
from pathlib import Path

import pytest

from conftest import ROOT
from vwg.io.record import read_record

TAG = f"cp{sys.version_info[0]}{sys.version_info[1]}"
WHEELS = sorted((ROOT / "dist").glob(f"vwg-*-{TAG}-{TAG}-manylinux_*.whl"))


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """A new venv with the wheel (and pybind11, for the C++ example that hosts Python) and nothing of the
    source tree: its python."""
    if not WHEELS:
        pytest.skip(f"no wheel for {TAG} in dist/: `make wheel-test` makes it and runs these tests")
    folder = tmp_path_factory.mktemp("wheel-venv")
    venv.EnvBuilder(with_pip=True).create(folder)
    python = folder / "bin" / "python"
    done = subprocess.run([str(python), "-m", "pip", "install", "-q", str(WHEELS[-1]), "pybind11>=2.12"],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    return python


def clean_env() -> dict[str, str]:
    """The environment without this checkout's PYTHONPATH: the venv's vwg is the wheel's."""
    return {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_PRELOAD")}


def run(*args: str, cwd: Path, **kw) -> subprocess.CompletedProcess[str]:
    return subprocess.run(list(args), cwd=cwd, capture_output=True, text=True, timeout=900, env=clean_env(), **kw)


@pytest.mark.slow
def test_the_wheel_runs_a_world_from_anywhere_and_gives_the_source_build_s_frames(installed, tmp_path):
    where = run(str(installed), "-c", "import vwg; print(vwg.__file__)", cwd=tmp_path)
    assert str(installed.parent.parent) in where.stdout, "the venv's vwg is not the wheel's"
    done = run(str(installed), "-m", "vwg", "run", "office", "--goal", "kitchen", "--record", "wheel.jsonl",
               "--threads", "2", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    source = subprocess.run([sys.executable, "-m", "vwg.cli", "run", "office", "--goal", "kitchen", "--record",
                             "source.jsonl", "--threads", "1"], cwd=tmp_path, capture_output=True, text=True,
                            timeout=900)
    assert source.returncode == 0, source.stderr
    a, b = read_record(tmp_path / "wheel.jsonl").frames, read_record(tmp_path / "source.jsonl").frames
    assert len(a) == len(b) > 100
    # Frame for frame the same events, strings and blobs; the chain links differ, as the headers name
    # different world files (the wheel's shipped copy and this checkout's).
    def line(frame: dict) -> str:
        return json.dumps({k: v for k, v in frame.items() if k != "prev"}, sort_keys=True)

    assert all(line(x) == line(y) for x, y in zip(a, b, strict=True))
    # The `vwg` command of the venv, in a folder far from this checkout: the shipped worlds are listed and run.
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    command = str(installed.parent / "vwg")
    listed = run(command, "worlds", cwd=elsewhere)
    assert all(f"\n  {name} " in listed.stdout for name in ("field", "maze", "office", "warehouse", "willow")), listed
    maze = run(command, "run", "maze", "--goal", "dead_end_1_0", "--summary-json", "s.json", cwd=elsewhere)
    assert maze.returncode == 0 and "reached      yes" in maze.stdout, maze.stdout + maze.stderr
    assert json.loads((elsewhere / "s.json").read_text())["reached"] is True


def manylinux_whitelist(policy: str) -> set[str]:
    """The system libraries a wheel of `policy` may need, as auditwheel (the peer checker) lists them."""
    import auditwheel

    policies = json.loads((Path(auditwheel.__file__).parent / "policy" / "manylinux-policy.json").read_text())
    return set(next(p["lib_whitelist"] for p in policies if p["name"] == policy))


def needed(library: Path) -> list[str]:
    """The libraries an ELF file names as DT_NEEDED (pyelftools, which auditwheel uses)."""
    from elftools.elf.dynamic import DynamicSection
    from elftools.elf.elffile import ELFFile

    with library.open("rb") as f:
        for section in ELFFile(f).iter_sections():
            if isinstance(section, DynamicSection):
                return [tag.needed for tag in section.iter_tags() if tag.entry.d_tag == "DT_NEEDED"]
    return []


@pytest.mark.slow
def test_the_extension_finds_every_library_in_the_wheel_or_the_base_system(installed, tmp_path):
    site = Path(run(str(installed), "-c", "import vwg, os; print(os.path.dirname(vwg.__file__))",
                    cwd=tmp_path).stdout.strip())
    extension = next(site.glob("_core*.so"))
    ldd = run("ldd", str(extension), cwd=tmp_path)
    assert ldd.returncode == 0 and "not found" not in ldd.stdout, ldd.stdout + ldd.stderr
    # What the extension and each library bundled with it need is bundled too, or one of the libraries the
    # wheel's policy lets it take from the system (what those bring along is the system's own business).
    policy = "manylinux_2_36"  # the wheel's (make wheel: WHEEL_PLAT)
    allowed = manylinux_whitelist(policy) | {"ld-linux-x86-64.so.2"}  # and the dynamic loader itself
    bundled = sorted((site.parent / "vwg.libs").iterdir())
    assert bundled, "nothing bundled: auditwheel did not repair this wheel"
    names = {p.name for p in bundled}
    for library in [extension, *bundled]:
        for name in needed(library):
            assert name in names or name in allowed, f"{library.name} needs {name}: neither bundled nor in {policy}"


@pytest.mark.slow
def test_the_sdk_builds_a_core_project_and_one_that_hosts_python(installed, tmp_path):
    cmake_dir = run(str(installed), "-m", "vwg", "--cmake-dir", cwd=tmp_path).stdout.strip()
    assert (Path(cmake_dir) / "vwgConfig.cmake").is_file()
    pybind = run(str(installed), "-m", "pybind11", "--cmakedir", cwd=tmp_path).stdout.strip()
    build = tmp_path / "example"
    configure = run("cmake", "-S", str(ROOT / "examples" / "cpp"), "-B", str(build), "-DVWG_EXAMPLE_COMPONENTS=core",
                    "-DVWG_EXAMPLE_PYTHON=ON", f"-Dvwg_DIR={cmake_dir}", f"-Dpybind11_DIR={pybind}",
                    f"-DPython_EXECUTABLE={installed}", cwd=tmp_path)
    assert configure.returncode == 0, configure.stdout + configure.stderr
    made = run("cmake", "--build", str(build), "-j", "2", cwd=tmp_path)
    assert made.returncode == 0, made.stdout + made.stderr
    balls = run(str(build / "bouncing_balls"), cwd=tmp_path)
    assert balls.returncode == 0 and "2000 discs drawn" in balls.stdout, balls.stdout + balls.stderr
    hosted = run(str(build / "python_actor"), cwd=tmp_path)
    assert hosted.returncode == 0 and "Counter<n=100, total=4950>" in hosted.stdout, hosted.stdout + hosted.stderr


@pytest.mark.slow
def test_the_sdk_refuses_a_component_it_does_not_carry(installed, tmp_path):
    cmake_dir = run(str(installed), "-m", "vwg", "--cmake-dir", cwd=tmp_path).stdout.strip()
    done = run("cmake", "-S", str(ROOT / "examples" / "cpp"), "-B", str(tmp_path / "sim"),
               "-DVWG_EXAMPLE_COMPONENTS=core;sim", f"-Dvwg_DIR={cmake_dir}", cwd=tmp_path)
    assert done.returncode != 0
    assert "'sim' needs the headers of Box2D" in done.stdout + done.stderr
    assert "build vwg from source" in done.stdout + done.stderr


def test_no_sdk_in_a_source_tree_is_said(tmp_path):
    # The source tree's vwg (no SDK folder), with the compiled module of the vwg this test runs: said, with
    # what to do. A copy, so that a checkout with or without a built-in-place module gives the same case.
    import shutil

    import vwg._core

    package = tmp_path / "vwg"
    shutil.copytree(ROOT / "python" / "vwg", package, ignore=shutil.ignore_patterns("sdk", "__pycache__", "_core*.so"))
    compiled = Path(vwg._core.__file__).resolve()
    (package / compiled.name).symlink_to(compiled)
    done = subprocess.run([sys.executable, "-m", "vwg", "--cmake-dir"], capture_output=True, text=True, timeout=120,
                          env={**clean_env(), "PYTHONPATH": str(tmp_path)}, cwd=tmp_path)
    assert done.returncode == 2 and "has no C++ SDK" in done.stderr, done.stderr
