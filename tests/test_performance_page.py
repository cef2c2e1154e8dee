"""The performance page's tables (tools/docs/performance.py) and the results files they come from
(benchmarks/results/<machine>/<bench>.json, written by benchmarks/machine.py:write_results)."""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path
from types import ModuleType

import pytest

from conftest import ROOT

RESULTS = ROOT / "benchmarks" / "results"


def load(name: str, path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


performance = load("vwg_docs_performance", ROOT / "tools" / "docs" / "performance.py")
machine = load("vwg_bench_machine", ROOT / "benchmarks" / "machine.py")


def write(path: Path, data: object) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2) + "\n")


def described(cpu: str, family: str, model: str, **more: object) -> dict[str, object]:
    return {"machine": "x86_64", "cpu_model": cpu, "cpu_family": family, "cpu_model_number": model,
            "simd": ["avx2"], "cores": 2, "python": "3.11.7", **more}


def test_a_section_per_machine_with_each_benchmarks_date_and_command(tmp_path):
    write(tmp_path / "amd-epyc-f25-m17" / "bench_frame.json",
          {**described("AMD EPYC", "25", "17"), "date": "2026-11-29T05:46:55+00:00",
           "command": "python benchmarks/bench_frame.py --quick", "quick": True,
           "rows": [{"robots": 10, "planner": "astar", "robot_steps_per_s": 12077.4, "ratio": 0.5}]})
    write(tmp_path / "intel-xeon-f6-m106" / "bench_frame.json",
          {**described("Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz", "6", "106", cores=8),
           "date": "2026-12-01T10:00:00+00:00", "command": "python benchmarks/bench_frame.py",
           "rows": [{"robots": 100, "planner": "random", "robot_steps_per_s": 8554.17, "ratio": 0.1084}]})
    page = performance.performance_markdown(tmp_path)
    headings = [line for line in page.splitlines() if line.startswith("## ")]
    assert headings == ["## AMD EPYC · family 25, model 17 · AVX2 · 2 cores",
                        "## Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz · family 6, model 106 · AVX2 · 8 cores"]
    assert "`python benchmarks/bench_frame.py --quick`, 2026-11-29 05:46 UTC" in page
    assert "`python benchmarks/bench_frame.py`, 2026-12-01 10:00 UTC" in page
    assert "| robots | planner | robot steps per s | ratio |" in page
    assert "| 10 | astar | 12,077 | 0.5 |" in page
    assert "| 100 | random | 8,554 | 0.1084 |" in page
    assert page.index("AMD EPYC") < page.index("12,077") < page.index("Intel") < page.index("8,554")


def test_a_missing_field_is_said_not_a_crash(tmp_path):
    write(tmp_path / "unknown-x86_64" / "bench_camera.json", {"machine": "x86_64", "render_fps": 836.16, "frames": 274})
    page = performance.performance_markdown(tmp_path)
    assert "## CPU not recorded (x86\\_64)" in page
    assert "not recorded: CPU family and model, SIMD, cores" in page
    assert "Command not recorded, date not recorded" in page
    assert "| render fps | 836.2 |" in page
    assert "| frames | 274 |" in page


def test_inferred_dates_and_commands_say_so(tmp_path):
    write(tmp_path / "amd-epyc-f25-m1" / "bench_core.json",
          {**described("AMD EPYC", "25", "1"), "date": "2026-11-21T07:26:54+00:00", "date_inferred": True,
           "command": "python benchmarks/bench_core.py", "command_inferred": True, "symbols_per_s": 6.9e7})
    page = performance.performance_markdown(tmp_path)
    assert "(the command inferred from the file's options)" in page
    assert "(the date of the commit that wrote the file)" in page
    assert "| symbols per s | 69,000,000 |" in page


def test_nested_values_become_columns_or_compact_text(tmp_path):
    write(tmp_path / "m" / "bench_x.json", {
        **described("AMD EPYC", "25", "17"), "date": "2026-11-29T00:00:00+00:00", "command": "python x.py",
        "laser": {"office": {"rays_per_s": 2.46e7, "codes": {"avx2": 2.56e7, "none": 8.86e6}}},
        "crowd": {"robots": 100, "recorded_over_plain": 7.012},
        "rows": [{"map": "8room_000.map", "trace_mb": [[20, 135.48], [45, 136.49], [70, 137.27], [95, 138.2],
                                                      [120, 138.5], [145, 138.9], [600, 141.73]],
                  "fps": math.nan, "rss_per_robot_mb": None, "equal": True}]})
    page = performance.performance_markdown(tmp_path)
    assert "|  | rays per s | codes · avx2 | codes · none |" in page
    assert "| office | 24,600,000 | 25,600,000 | 8,860,000 |" in page
    assert "**crowd**" in page and "| recorded over plain | 7.012 |" in page
    assert "| 8room\\_000.map | 7 values: (20, 135.5), (45, 136.5), …, (600, 141.7) | — | — | yes |" in page


def test_a_malformed_file_is_named(tmp_path):
    (tmp_path / "amd-epyc-f25-m1").mkdir()
    bad = tmp_path / "amd-epyc-f25-m1" / "bench_gym.json"
    bad.write_text('{"machine": "x86_64", "rows": [')
    with pytest.raises(ValueError, match=r"bench_gym\.json: not valid JSON"):
        performance.performance_markdown(tmp_path)
    bad.write_text("[1, 2]")
    with pytest.raises(ValueError, match=r"bench_gym\.json: a results file is a JSON object, not list"):
        performance.performance_markdown(tmp_path)


def test_a_results_file_outside_a_machine_folder_is_named(tmp_path):
    write(tmp_path / "bench_core.json", {"machine": "x86_64"})
    with pytest.raises(ValueError, match=r"bench_core\.json: a results file belongs in a folder per machine"):
        performance.performance_markdown(tmp_path)


def test_no_results_is_said(tmp_path):
    assert "No benchmark results" in performance.performance_markdown(tmp_path)


def test_write_results_writes_the_machines_folder_and_the_history(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(ROOT / "benchmarks" / "bench_x.py"), "--quick"])
    monkeypatch.chdir(tmp_path)
    out = machine.write_results(tmp_path / "results" / "bench_x.json", quick=True, rows=[{"robots": 1, "rate": 2.5}],
                                machine={"platform": "Linux", "vwg": "0.1.0"})
    data = json.loads(out.read_text())
    assert out == tmp_path / "results" / machine.machine_id(data) / "bench_x.json"
    assert data["command"] == "python benchmarks/bench_x.py --quick"
    assert data["date"].endswith("+00:00") and data["bench"] == "bench_x"
    assert data["platform"] == "Linux" and data["vwg"] == "0.1.0" and isinstance(data["machine"], str)
    history = (tmp_path / "results" / "history.jsonl").read_text().splitlines()
    assert [json.loads(line) for line in history] == [data]
    machine.write_results(tmp_path / "results" / "bench_x.json", quick=False, rows=[])
    assert len((tmp_path / "results" / "history.jsonl").read_text().splitlines()) == 2
    assert "`python benchmarks/bench_x.py --quick`" in performance.performance_markdown(tmp_path / "results")


@pytest.mark.parametrize(("cpu", "expected"), [
    ({"cpu_model": "AMD EPYC", "cpu_family": "25", "cpu_model_number": "17"}, "amd-epyc-f25-m17"),
    ({"cpu_model": "Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz", "cpu_family": "6", "cpu_model_number": "106"},
     "intel-xeon-f6-m106"),
    ({"machine": "x86_64"}, "unknown-x86_64"),
])
def test_machine_ids_are_short_names_of_the_cpu(cpu, expected):
    assert machine.machine_id(cpu) == expected


RESULT_FILES = sorted(RESULTS.glob("*/*.json"))


def test_there_are_results():
    assert RESULT_FILES
    assert not list(RESULTS.glob("*.json")), "a results file outside a machine folder"


@pytest.mark.parametrize("path", RESULT_FILES, ids=[p.relative_to(RESULTS).as_posix() for p in RESULT_FILES])
def test_every_results_file_names_its_machine_date_and_command(path):
    data = json.loads(path.read_text())
    for field in ("machine", "date", "command"):
        assert data.get(field), f"{path}: no {field}"
    assert data["command"].startswith("python benchmarks/bench_"), path
    assert path.parent.name == machine.machine_id(data), f"{path}: in the folder of another machine"


def canonical(record: object) -> str:
    return json.dumps(record, sort_keys=True)  # NaN != NaN, but its text is equal


def test_the_history_holds_every_results_file():
    records = [json.loads(line) for line in (RESULTS / "history.jsonl").read_text().splitlines()]
    for record in records:
        assert record.get("machine") and record.get("date") and record.get("command"), record.get("bench")
    history = {canonical(record) for record in records}
    for path in RESULT_FILES:
        assert canonical(json.loads(path.read_text())) in history, f"{path} is not in history.jsonl"


def test_the_page_renders_every_results_file():
    page = performance.performance_markdown(RESULTS)
    for path in RESULT_FILES:
        assert f"### `{path.stem}`" in page


CPUINFO = """processor\t: 0
vendor_id\t: AuthenticAMD
cpu family\t: 25
model\t\t: 17
model name\t: AMD EPYC 9R14 96-Core Processor
flags\t\t: fpu vme de pse avx avx2 bmi2 avx512f avx512dq

processor\t: 1
vendor_id\t: AuthenticAMD
model name\t: not the first processor
"""


def test_the_machine_is_described_from_the_first_processor_of_cpuinfo():
    from vwg.machine import cpu, summary

    described = cpu(CPUINFO)
    assert described == {"cpu_model": "AMD EPYC 9R14 96-Core Processor", "cpu_family": "25", "cpu_model_number": "17",
                         "simd": ["avx2", "avx512f"]}
    assert summary({**described, "cores": 2, "machine": "x86_64"}) == \
        "AMD EPYC 9R14 96-Core Processor (family 25, model 17; AVX2, AVX-512F), 2 cores, x86_64"
    # No AVX2, one core, nothing of the family: said, not left out silently.
    assert summary({"cpu_model": "Old", "simd": [], "cores": 1}) == "Old (no AVX2), 1 core"
    assert cpu("") == {} and summary({}) == "a CPU of unknown name"
    # The benchmarks' results files describe the machine with the same function.
    assert machine.cpu is cpu
