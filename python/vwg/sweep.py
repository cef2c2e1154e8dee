"""Sweeps: the cartesian product of worlds × planners × seeds × parameter grids, run on Dask.

    vwg sweep SPEC.yaml -o results.csv [--scheduler tcp://HOST:PORT] [--workers N]

A SPEC is YAML::

    worlds: [office, maze]          # shipped names, or files (relative to the SPEC's folder)
    planners: [random, astar]
    seeds: 10                       # 0..9; or a list: [3, 7]
    frames: 600                     # the frame limit of every run
    params:                         # optional: each key a list of values (vwg.trial.KNOWN_PARAMS)
      task: [random]
      sensors: [[laser], [kinect]]

Each cell is a vwg.trial.Trial, sent to a worker as plain data (the worker builds its own engine);
each worker runs one cell at a time on one thread. Dask (``dask.distributed``) does the distributing:
a local cluster of one process per core by default, or the scheduler given. Rows are appended to
the CSV as cells finish (vwg.trial.COLUMNS); a rerun reads the CSV, skips the cells it holds and
finishes at once when none is left, so a stopped sweep resumes where it was.
"""

from __future__ import annotations

import contextlib
import csv
import itertools
import math
import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from vwg.errors import Error, SchemaError
from vwg.io.shipped import expand_user, shipped_world, shipped_worlds, unusable_name
from vwg.io.yamldoc import YamlDoc
from vwg.plugins import deciders
from vwg.trial import COLUMNS, KNOWN_PARAMS, Trial, check_params, run_trial

__all__ = ["SweepResult", "SweepSpec", "dask_client", "finished_keys", "load_spec", "run_sweep"]

SPEC_KEYS = ("worlds", "planners", "seeds", "frames", "params")
MAX_CELLS = 1_000_000


@dataclass
class SweepSpec:
    """What a sweep runs; ``trials()`` lists its cells in a fixed order."""

    worlds: list[str]
    planners: list[str]
    seeds: list[int]
    frames: int
    params: dict[str, list[Any]] = field(default_factory=dict)
    #: More parameter grids, each run over the same worlds, planners and seeds after `params`' (an experiment's
    #: variant that does not cross every other value: test 5's people, with avoidance, on the unboxed maps).
    more: list[dict[str, list[Any]]] = field(default_factory=list)

    def trials(self) -> list[Trial]:
        out = []
        for params in (self.params, *self.more):
            names = list(params)
            grids = [params[n] for n in names]
            out += [Trial(world, planner, seed, self.frames, dict(zip(names, values, strict=True)))
                    for world, planner, values, seed in itertools.product(self.worlds, self.planners,
                                                                          itertools.product(*grids), self.seeds)]
        return out

    def __len__(self) -> int:
        cells = sum(math.prod(len(v) for v in params.values()) for params in (self.params, *self.more))
        return len(self.worlds) * len(self.planners) * len(self.seeds) * cells


def load_spec(path: str | Path) -> SweepSpec:
    """Read and check a SPEC file; errors name the file, line and field."""

    doc = YamlDoc(path)
    base = Path(path).resolve().parent
    if not isinstance(doc.data, dict):
        raise doc.error((), f"expected a mapping with {', '.join(SPEC_KEYS)}, got {type(doc.data).__name__}")
    for key in doc.data:
        if key not in SPEC_KEYS:
            raise doc.error((key,), f"unknown key (expected: {', '.join(SPEC_KEYS)})")
    worlds = []
    for i, name in enumerate(_nonempty_list(doc, ("worlds",))):
        if not isinstance(name, str):
            raise doc.error(("worlds", i), f"expected a world file or a shipped world's name, got {name!r}")
        try:
            worlds.append(_world_name(name, base))
        except Error as e:
            raise doc.error(("worlds", i), str(e)) from None
    planners = []
    for i, name in enumerate(_nonempty_list(doc, ("planners",))):
        if not isinstance(name, str) or name.lower() not in deciders:
            raise doc.error(("planners", i), f"unknown planner {name!r} (known: {', '.join(deciders)})")
        planners.append(name.lower())
    raw_seeds = doc.get(("seeds",), (int, list))
    if isinstance(raw_seeds, int):
        if not 1 <= raw_seeds <= MAX_CELLS:
            raise doc.error(("seeds",), f"expected a count of seeds from 1 to {MAX_CELLS} (or a list), got {raw_seeds}")
        seeds = list(range(raw_seeds))
    else:
        seeds = [doc.number(("seeds", i), integer=True, minimum=0, maximum=2**63 - 1) for i in range(len(raw_seeds))]
        if not seeds:
            raise doc.error(("seeds",), "expected at least one seed")
        _nonempty_list(doc, ("seeds",))
    frames = doc.number(("frames",), integer=True, minimum=1, maximum=10_000_000)
    params: dict[str, list[Any]] = {}
    for name in doc.get(("params",), dict, default={}):
        if name not in KNOWN_PARAMS:
            raise doc.error(("params", name), f"unknown parameter (known: {', '.join(KNOWN_PARAMS)})")
        values = _nonempty_list(doc, ("params", name))
        for i, value in enumerate(values):
            try:
                check_params({name: value}, "params")
            except SchemaError as e:
                raise doc.error(("params", name, i), str(e).split(": ", 1)[1]) from None
        params[name] = values
    spec = SweepSpec(worlds, planners, seeds, frames, params)
    if len(spec) > MAX_CELLS:
        raise doc.error((), f"{len(spec)} cells: more than {MAX_CELLS}")
    return spec


def _nonempty_list(doc: YamlDoc, path: tuple[Any, ...]) -> list[Any]:
    """A non-empty list without repeats (a repeat would run the same cells twice)."""
    value = doc.get(path, list)
    if not value:
        raise doc.error(path, "expected a non-empty list")
    seen: list[Any] = []
    for i, item in enumerate(value):
        if item in seen and type(item) is type(seen[seen.index(item)]):
            raise doc.error((*path, i), f"{item!r} is listed twice")
        seen.append(item)
    return value


def _world_name(name: str, base: Path) -> str:
    """How a cell names its world: a file's absolute path (relative names are taken from the SPEC's
    folder), or a shipped world's name (it travels by name: a worker may have vwg installed elsewhere)."""

    local = base / expand_user(name)
    try:
        is_file, exists = local.is_file(), local.exists()
    except (OSError, ValueError) as e:  # a name longer than the system takes (ENAMETOOLONG)
        raise unusable_name(name, e) from None
    if is_file:
        return str(local)
    if exists:
        raise Error(f"{local}: is not a file (expected a robot world file, .yaml)")
    if Path(name).parent == Path(".") and shipped_world(name) is not None:
        return name.removesuffix(".yaml")
    raise Error(f"{name}: no file {local}, and no shipped world of that name (shipped: {', '.join(shipped_worlds())})")


HEADER_LINE = ",".join(COLUMNS) + "\r\n"  # as csv.DictWriter writes it


@dataclass
class _ResultsFile:
    """What a results file holds: the ``keys`` of its finished cells (the first five columns of each
    complete row after the header) and ``good_bytes``, where its last complete record ends. Bytes after
    that are what a stop left half-written (``torn`` says what): a last row, or the header."""

    keys: set[tuple[str, ...]] = field(default_factory=set)
    good_bytes: int = 0
    torn: str = ""
    torn_header: bool = False


def _read_results(out: Path) -> _ResultsFile:
    """Read a results file record by record (a quoted field may hold a line break), streaming: only
    records that end with their line break count; a last one without is torn (not finished)."""
    if not out.exists() or out.stat().st_size == 0:
        return _ResultsFile()
    size = out.stat().st_size
    found = _ResultsFile()
    # surrogateescape: a stop may cut a character in two, and each line's bytes are counted exactly
    with out.open(newline="", encoding="utf-8", errors="surrogateescape") as f:
        head = f.read(len(HEADER_LINE) + 1)
        if HEADER_LINE.startswith(head) and head != HEADER_LINE:
            return _ResultsFile(torn=f"{out}: its header was cut short", torn_header=True)
        f.seek(0)
        consumed = 0
        last_line = ""

        def counted() -> Iterator[str]:
            nonlocal consumed, last_line
            for text in f:
                consumed += len(text.encode("utf-8", "surrogateescape"))
                last_line = text
                yield text

        # strict: a quote a stop left open raises at the end here, rather than passing for a record
        reader = csv.reader(counted(), strict=True)
        header: list[str] | None = None
        line = 1  # where the record being read starts
        try:
            for fields in reader:
                if fields and consumed == size and not last_line.endswith("\n"):  # its line break never written
                    found.torn = f"{out}: line {line} was left half-written"
                    break
                if header is None:
                    header = fields
                    if header != list(COLUMNS):
                        break
                elif len(fields) == len(COLUMNS):
                    found.keys.add(tuple(fields[:5]))
                found.good_bytes = consumed
                line = reader.line_num + 1
        except csv.Error as e:
            if consumed < size:  # broken in the middle, not torn at the end
                raise Error(f"{out}:{reader.line_num}: not a row as vwg sweep writes them ({e}); mend or delete "
                            "that line, or name another file with -o") from None
            found.torn = f"{out}: line {line} was left half-written"
    if header != list(COLUMNS):
        raise Error(f"{out}: not a results file of vwg sweep (its first line is not the header "
                    f"{','.join(COLUMNS)}); name another file with -o, or move this one away")
    return found


def finished_keys(out: Path) -> set[tuple[str, ...]]:
    """The cells a results file holds already (their first five columns). A row a stop left
    half-written at the end (even one that lacks only its line break) is not finished: its cell runs again."""
    return _read_results(out).keys


@dataclass
class SweepResult:
    cells: int      # in the spec
    done_before: int  # found in the results file
    ran: int        # run now
    failed: int     # of those, rows with an error
    out: Path
    repaired: str = ""  # what was mended in the results file before the sweep (a torn last row or header)
    reached: int = 0  # of those run now, rows whose every robot reached its room


def run_sweep(spec: SweepSpec, out: str | Path, *, scheduler: str | None = None, workers: int | None = None,
              progress: bool | None = None, on_row: Callable[[dict[str, Any]], None] | None = None,
              client: Any = None) -> SweepResult:
    """Run the cells of `spec` not yet in `out` on Dask, appending a row per cell as it finishes;
    on `client` if given (several sweeps on one cluster), else on a cluster of its own (dask_client)."""
    out = Path(out)
    trials = spec.trials()
    # The torn tail is cut before the finished cells are counted: a row cut short (even one that lacks
    # only its line break) is not counted as done, and its cell runs again.
    repaired = _repair(out)
    done = finished_keys(out)
    todo = [t for t in trials if t.key not in done]
    result = SweepResult(len(trials), len(trials) - len(todo), 0, 0, out, repaired)
    if not todo:
        return result
    new_file = not out.exists() or out.stat().st_size == 0
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("a", newline="", encoding="utf-8") as f, \
            (contextlib.nullcontext(client) if client is not None else dask_client(scheduler, workers)) as client:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        if new_file:
            writer.writeheader()
            f.flush()
        for row in _progress(_results(client, todo), len(todo), progress):
            writer.writerow(row)
            f.flush()  # a stop loses no finished cell
            result.ran += 1
            result.failed += bool(row["error"])
            result.reached += int(str(row.get("reached")).lower() in ("true", "1"))
            if on_row is not None:
                on_row(row)
    return result


def _repair(out: Path) -> str:
    """Cut what a stop left half-written off the end of a results file: a last row (a quote it left
    open would swallow the next row) or the header (the file is then started again). Says what it cut."""
    found = _read_results(out)
    if not found.torn:
        return ""
    with out.open("rb+") as f:
        f.truncate(found.good_bytes)
    if found.torn_header:
        return f"{found.torn}: started again"
    return f"{found.torn} (a stop in the middle of writing it): cut off, its cell runs again"


def _results(client: Any, trials: list[Trial]) -> Iterator[dict[str, Any]]:
    from dask.distributed import as_completed

    # Plain dicts go to the workers; each cell is its own task under a fresh key (pure=False: never
    # merged with another, nor with a cell of an earlier sweep on the same client).
    futures = [client.submit(run_trial, _plain(t), pure=False) for t in trials]
    for future in as_completed(futures):
        yield future.result()
        future.release()


def _plain(trial: Trial) -> dict[str, Any]:
    return {"world": trial.world, "planner": trial.planner, "seed": trial.seed, "frames": trial.frames,
            "params": dict(trial.params)}


@contextlib.contextmanager
def dask_client(scheduler: str | None, workers: int | None) -> Iterator[Any]:
    """A Dask client: on the scheduler given, or on a local cluster of `workers` processes (default:
    the machine's cores) of one thread each, on 127.0.0.1, closed afterwards."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise Error("vwg sweep runs on Dask: pip install 'vwg[sweep]' (dask[distributed])") from None
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except OSError as e:
            raise Error(f"--scheduler {scheduler}: cannot reach the Dask scheduler ({e})") from None
        with client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    # Everything on 127.0.0.1; the scheduler's status page on a free port (two sweeps at once do not clash).
    # Dask's own messages only when critical: a worker's heartbeat cut short as the cluster closes
    # logs a traceback that is not a fault of the sweep.
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0", host="127.0.0.1",
                      silence_logs=50) as cluster, Client(cluster) as client:
        yield client


def _progress(rows: Iterator[dict[str, Any]], total: int, show: bool | None) -> Iterator[dict[str, Any]]:
    import sys

    from tqdm import tqdm

    disable = not sys.stderr.isatty() if show is None else not show
    with tqdm(total=total, desc="cells", unit="cell", disable=disable) as bar:
        for row in rows:
            yield row
            bar.update(1)


def describe_params() -> str:
    """The parameters a SPEC's params may set, one per line."""
    return "\n".join(f"  {name}: {meaning}" for name, (_, meaning) in KNOWN_PARAMS.items())
