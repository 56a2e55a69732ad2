"""Datasets of grooms on a Dask cluster (docs/batch.md, "Dask"): the items of a batch spec mapped
over the worker processes of a ``distributed`` cluster, each made by the library exactly as
``ringlet batch`` makes it (the same files, byte for byte), skipping the items already done.

    import ringlet.batch
    summary = ringlet.batch.run("examples/batch/small.json", "out/small")   # a local cluster
    summary = ringlet.batch.run(spec, out, client=distributed.Client("tcp://host:8786"))

    /usr/bin/python3 -m ringlet.batch SPEC -o OUT [--scheduler tcp://HOST:PORT] [--workers N]

Items are pure functions of (spec, index): any worker can make any item, any number of times, and
write the same bytes. An item folder is written all or nothing (a temporary folder renamed into
place, ``done`` last), so an item whose worker is killed while making or writing it is simply
made again: Dask reschedules the tasks of a dead worker on the others by itself
(``distributed.scheduler.allowed-failures`` times, 3 by default), and the half-written
temporary of the dead one is never taken for the item. The client writes the manifest (one line
per item made in this run, under the library's flock) and the summary; it and the workers must
see the spec, its bases and the output directory at the same paths (a shared file system, as
for Slurm).

Needs python3-distributed (Debian 12: python3-dask, python3-distributed 2022.12) for ``run``;
python3-tqdm for the progress bar (without it, no bar). ``run_items`` needs neither.
"""
import argparse
import dataclasses
import hashlib
import os
import shutil
import socket
import sys
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

from . import _ringlet
from ._ringlet import BatchSpec, Error

__all__ = ["BatchSummary", "run", "run_items", "main"]

# Per worker process: the checked spec of the run (reading a head mesh takes seconds; every
# task of a worker shares it). Keyed by the spec's absolute path and the SHA-256 of its text.
_SPECS: Dict[Tuple[str, str], BatchSpec] = {}


@dataclasses.dataclass
class BatchSummary:
    """What a run did, counted like ``ringlet batch``'s summary line."""
    total: int          #: items of the run's range
    begin: int          #: the range [begin, end)
    end: int
    count: int          #: items of the spec
    done: int = 0       #: made now, clean
    flagged: int = 0    #: made now, with unconverged or unstable masters (kept, flagged)
    failed: int = 0     #: not made: (name, one-line error) in failures
    skipped: int = 0    #: already done when the run started
    seconds: float = 0.0
    workers: int = 0    #: Dask workers when the run started
    output: str = ""
    failures: List[Tuple[str, str]] = dataclasses.field(default_factory=list)
    #: per item made now: {"item", "name", "status", "worker", "pid", "seconds" (wall),
    #: "cpu_seconds" (its worker process's CPU time meanwhile), "timing" (timing.json)}
    items: List[Dict[str, Any]] = dataclasses.field(default_factory=list)
    #: temporary folders of workers that died while writing an item, removed at the end
    removed_temporaries: List[str] = dataclasses.field(default_factory=list)

    @property
    def ok(self) -> bool:
        """Every item of the range is done (now or before), none flagged or failed."""
        return self.failed == 0 and self.flagged == 0

    def line(self) -> str:
        """The summary line, as ``ringlet batch`` prints it (plus the workers, when some item
        was to be made)."""
        workers = " on %d Dask workers" % self.workers if self.workers else ""
        return ("batch: %d items [%d, %d) of %d: %d done, %d flagged, %d failed, %d skipped in "
                "%s%s -> %s" % (
                    self.total, self.begin, self.end, self.count, self.done, self.flagged,
                    self.failed, self.skipped, _format_seconds(self.seconds), workers,
                    self.output))


def _format_seconds(seconds: float) -> str:
    if seconds < 1.0:
        return "%.1f ms" % (seconds * 1e3)
    if seconds < 120.0:
        return "%.2f s" % seconds
    if seconds < 7200.0:
        return "%.1f min" % (seconds / 60.0)
    return "%.1f h" % (seconds / 3600.0)


def _digest(path: str) -> str:
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def _spec(path: str, digest: str) -> BatchSpec:
    """The checked spec at path (cached per process), refusing a file changed since the client
    read it: the items of one run come from one spec."""
    key = (path, digest)
    spec = _SPECS.get(key)
    if spec is None:
        try:
            now = _digest(path)
        except OSError as e:
            raise Error("%s: cannot read the spec on this worker: %s (the workers must see "
                        "it at the client's path)" % (path, e.strerror)) from None
        if now != digest:
            raise Error("%s: changed since the run started (its SHA-256 differs on this "
                        "worker)" % path)
        spec = BatchSpec(path)
        _SPECS.clear()
        _SPECS[key] = spec
    return spec


def _host_and_pid() -> Tuple[str, int]:
    """This process's host name as the library names temporary folders (batch_store.cpp,
    HostName: '/', '.' and control characters as '_') and its process id."""
    host = "".join("_" if c in "/." or ord(c) < 0x20 else c for c in socket.gethostname())
    return host or "host", os.getpid()


def _remove_temporaries(outdir: str, processes: Sequence[Tuple[str, int]]) -> List[str]:
    """Removes the temporary item folders (.item-NNNNNNNNN.tmp.HOST.PID) of dead worker
    processes: the remains of an item whose worker was killed while writing it (the item was
    made again by another). Returns their names."""
    suffixes = tuple(".tmp.%s.%d" % p for p in processes)
    removed = []
    if not suffixes:
        return removed
    for name in sorted(os.listdir(outdir)):
        if name.startswith(".item-") and name.endswith(suffixes):
            shutil.rmtree(os.path.join(outdir, name), ignore_errors=True)
            removed.append(name)
    return removed


def _run_task(spec_path: str, digest: str, outdir: str, indices: Sequence[int],
              threads: int) -> List[Dict[str, Any]]:
    """A Dask task: makes the items `indices` on this worker (run_batch_item each)."""
    spec = _spec(spec_path, digest)
    worker = ""
    try:
        from distributed import get_worker
        worker = get_worker().address
    except (ImportError, ValueError):
        pass
    results = []
    for index in indices:
        before = os.times()
        result = _ringlet.run_batch_item(spec, outdir, index, threads)
        after = os.times()
        result["worker"] = worker
        result["pid"] = os.getpid()
        # The worker process's CPU time (user + system, s) while making the item: the item's
        # threads and whatever else the worker did meanwhile (heartbeats: little).
        result["cpu_seconds"] = (after.user - before.user) + (after.system - before.system)
        results.append(result)
    return results


def run_items(spec, out: str, begin: int = 0, end: Optional[int] = None,
              threads: int = 0) -> List[Dict[str, Any]]:
    """Makes items [begin, end) of the spec into `out` in this process, one after another, as
    ``ringlet batch SPEC -o OUT --items BEGIN:END`` would (the same bytes), without recording
    spec.json or manifest lines. spec: a path or a BatchSpec. Returns run_batch_item's dicts."""
    if not isinstance(spec, BatchSpec):
        spec = BatchSpec(os.fspath(spec))
    end = spec.count if end is None else end
    if not 0 <= begin < end <= spec.count:
        raise Error("items: expected 0 <= begin < end <= %d, got [%d, %d)" %
                    (spec.count, begin, end))
    out = os.fspath(out)
    os.makedirs(out, exist_ok=True)
    return [_ringlet.run_batch_item(spec, out, k, threads) for k in range(begin, end)]


def _record_spec(outdir: str, spec_path: str) -> None:
    """OUTDIR/spec.json: the spec's own text, as ``ringlet batch`` records it; a directory holding
    another spec's dataset is refused."""
    with open(spec_path, "rb") as f:
        text = f.read()
    copy = os.path.join(outdir, "spec.json")
    for _ in range(2):
        if os.path.exists(copy):
            with open(copy, "rb") as f:
                if f.read() != text:
                    raise Error("%s: holds the dataset of another spec (its spec.json differs "
                                "from %s); give another output directory" % (outdir, spec_path))
            return
        temporary = "%s.tmp.%d" % (copy, os.getpid())
        with open(temporary, "wb") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        try:
            os.link(temporary, copy)  # fails if another process wrote it meanwhile: compare
        except FileExistsError:
            continue
        finally:
            os.unlink(temporary)
        return


def _manifest_name(items: Optional[Tuple[int, int]]) -> str:
    if items is None:
        return "manifest-all.jsonl"
    return "manifest-items-%d-%d.jsonl" % items


def _parse_items(text: str) -> Tuple[int, int]:
    try:
        a, b = text.split(":")
        if not (a.isdigit() and b.isdigit()):
            raise ValueError
        return int(a), int(b)
    except ValueError:
        raise Error('--items: expected A:B with integers 0 <= A < B (items A to B - 1), got '
                    '"%s"' % text) from None


def run(spec, out: str, client=None, *, items: Optional[Tuple[int, int]] = None,
        workers: Optional[int] = None, threads: Optional[int] = None, items_per_task: int = 1,
        progress: Optional[bool] = None, quiet: bool = False) -> BatchSummary:
    """Makes the items of a batch spec (a path) into the directory `out` on a Dask cluster.

    client: a ``distributed.Client``; None starts a LocalCluster of `workers` worker processes
    (default: the cores this process may use), one thread each, closed at the end. items:
    (A, B) runs items A to B - 1 only (default: all). threads: per item (default: 1 on the local
    cluster, 0 = all cores of the worker's machine with a given client: run one single-threaded
    worker per machine); the bytes do not depend on it. items_per_task: consecutive items per
    Dask task (more amortizes the scheduler's per-task cost on huge runs; a lost task re-runs
    only its items not yet done). progress: a tqdm bar on stderr (default: when stderr is a
    terminal). quiet: no summary line.

    Checks the spec first (a bad one raises ringlet.Error naming the field; nothing is
    written), records spec.json, skips the items already done, maps the others over the
    workers, appends one manifest line per item made (manifest-all.jsonl, or
    manifest-items-A-B.jsonl, as ``ringlet batch`` names them) and returns a BatchSummary. An
    item lost with a killed worker is made again on another (Dask's rescheduling); one whose
    task failed every time is counted as failed with the error.
    """
    start = time.monotonic()
    spec_path = os.path.abspath(os.fspath(spec))
    parsed = BatchSpec(spec_path)  # raises ringlet.Error with the field: nothing written yet
    begin, end = (0, parsed.count) if items is None else (int(items[0]), int(items[1]))
    if items is not None:
        if not 0 <= begin < end:
            raise Error('--items: expected A:B with integers 0 <= A < B (items A to B - 1), '
                        'got "%d:%d"' % (begin, end))
        if end > parsed.count:
            raise Error("--items: %d:%d goes beyond the spec's %d items (the last is %d)" %
                        (begin, end, parsed.count, parsed.count - 1))
    if items_per_task < 1:
        raise Error("items_per_task: expected an integer >= 1, got %r" % (items_per_task,))
    if workers is not None and (client is not None or workers < 1):
        raise Error("workers: expected an integer >= 1 and no client (the local cluster's "
                    "worker processes), got %r" % (workers,) +
                    (" with a client" if client is not None else ""))
    if threads is not None and not 0 <= threads <= 1024:
        raise Error("threads: expected an integer in [0, 1024] (0 = all cores), got %r" %
                    (threads,))
    out = os.fspath(out)
    if os.path.exists(out) and not os.path.isdir(out):
        raise Error("%s: exists and is not a directory" % out)
    os.makedirs(out, exist_ok=True)
    outdir = os.path.abspath(out)
    _record_spec(outdir, spec_path)
    manifest = os.path.join(outdir, _manifest_name(None if items is None else (begin, end)))
    summary = BatchSummary(total=end - begin, begin=begin, end=end, count=parsed.count,
                           output=out)

    todo = [k for k in range(begin, end)
            if not _ringlet.batch_item_done(outdir, _ringlet.batch_item_name(k))]
    summary.skipped = summary.total - len(todo)

    own_cluster = None
    if threads is None:
        threads = 1 if client is None else 0
    try:
        if client is None and todo:
            import dask
            from distributed import Client, LocalCluster
            n = workers or len(os.sched_getaffinity(0))
            # The worker processes without the nanny's MALLOC_TRIM_THRESHOLD_=65536 (Dask's
            # default; it also fixes glibc's mmap threshold, so that an item's large buffers are
            # mapped and unmapped again and again): it cost 29 % more CPU per item here
            # (docs/benchmarks.md, "Datasets"). The scheduler's HTTP server on a
            # free port (its default 8787 may be taken).
            environ = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}))
            environ.pop("MALLOC_TRIM_THRESHOLD_", None)
            with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}):
                own_cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           dashboard_address="127.0.0.1:0")
            client = Client(own_cluster)
        if todo:
            summary.workers = len(client.scheduler_info()["workers"])
            # Each worker's host and process, so that the temporary folders of the workers that
            # die during the run (killed while writing an item) can be removed at its end.
            processes = client.run(_host_and_pid)
            _map(client, parsed, spec_path, _digest(spec_path), outdir, todo, threads,
                 items_per_task, manifest, summary, progress)
            gone = set(processes) - set(client.scheduler_info()["workers"])
            summary.removed_temporaries = _remove_temporaries(
                outdir, [processes[a] for a in sorted(gone)])
    finally:
        if own_cluster is not None:
            if client is not None:
                client.close()
            own_cluster.close()
    summary.seconds = time.monotonic() - start
    if not quiet:
        print(summary.line(), flush=True)
    return summary


def _map(client, spec, spec_path, digest, outdir, todo, threads, items_per_task, manifest,
         summary, progress):
    from distributed import as_completed
    chunks = [todo[i:i + items_per_task] for i in range(0, len(todo), items_per_task)]
    # Task keys name their first item (the dashboard and client.processing() show them), and
    # the digest makes them unique per spec; pure=False: a rerun is a new task.
    futures = {}
    for chunk in chunks:
        key = "ringlet-batch-%s-%s-%s" % (_ringlet.batch_item_name(chunk[0]), len(chunk),
                                          digest[:12])
        future = client.submit(_run_task, spec_path, digest, outdir, chunk, threads, key=key,
                               pure=False)
        futures[future] = chunk
    bar = None
    if progress is None:
        progress = sys.stderr.isatty()
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(total=len(todo), unit="item", desc="batch", file=sys.stderr)
        except ImportError:
            bar = None
    try:
        for future in as_completed(list(futures)):
            chunk = futures.pop(future)
            try:
                results = future.result()
            except Exception as e:  # noqa: BLE001  (KilledWorker, a worker's error: record it)
                message = str(e).splitlines()[0] if str(e) else type(e).__name__
                results = [{"item": k, "name": _ringlet.batch_item_name(k), "status": "failed",
                            "error": "%s: %s" % (type(e).__name__, message), "worker": "",
                            "pid": 0, "seconds": 0.0, "timing": None, "manifest_line": None}
                           for k in chunk]
            for r in results:
                _account(r, manifest, summary, spec)
                if bar is not None:
                    bar.update(1)
            if bar is not None:
                bar.set_postfix(done=summary.done, flagged=summary.flagged,
                                failed=summary.failed, refresh=False)
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        if bar is not None:
            bar.close()


def _account(r, manifest, summary, spec):
    """Counts one item's result and appends its manifest line. An item its task found done (a
    previous attempt of the task, on a worker that died after writing it) counts as made by this
    run with its recorded status: the manifest then matches an undisturbed run's."""
    status = r["status"]
    if status == "skipped":
        status = r["recorded_status"]
    line = r.get("manifest_line")
    if line is None:  # a task that raised: the line `ringlet batch` writes for a failed item
        import json
        base = _ringlet.resolve_batch_item(spec, r["item"])["base"]
        line = json.dumps({"base": base, "error": r["error"], "item": r["item"],
                           "name": r["name"], "status": "failed"},
                          separators=(",", ":"), ensure_ascii=False)
    if status == "done":
        summary.done += 1
    elif status == "flagged":
        summary.flagged += 1
    else:
        summary.failed += 1
        summary.failures.append((r["name"], r["error"]))
        print("ringlet.batch: warning: %s: %s" % (r["name"], r["error"]), file=sys.stderr)
    _ringlet.append_manifest_line(manifest, line)
    record = {k: r.get(k) for k in ("item", "name", "worker", "pid", "seconds", "cpu_seconds",
                                    "timing")}
    record["status"] = status
    summary.items.append(record)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python3 -m ringlet.batch SPEC -o OUT [--scheduler ADDRESS] [--workers N] ...``: exit 0
    when every item of the range is done, 2 when some failed or were flagged, 1 on bad usage or
    a bad spec (one line on stderr; nothing written)."""
    parser = argparse.ArgumentParser(
        prog="python3 -m ringlet.batch",
        description="Make a dataset of grooms from a batch spec (docs/batch.md) on a Dask "
                    "cluster: the same files, byte for byte, as `ringlet batch`.")
    parser.add_argument("spec", help="batch spec (JSON, docs/batch.md)")
    parser.add_argument("-o", "--output", required=True, help="output directory")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler "
                        "(tcp://HOST:PORT); default: a local cluster of worker processes")
    parser.add_argument("--workers", type=int, help="worker processes of the local cluster "
                        "(default: the cores); not with --scheduler")
    parser.add_argument("--items", help="run items A to B - 1 only (A:B)")
    parser.add_argument("--threads", type=int, help="threads per item (default 1 on the local "
                        "cluster, 0 = all cores with --scheduler); the bytes do not depend on it")
    parser.add_argument("--items-per-task", type=int, default=1,
                        help="consecutive items per Dask task (default 1)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    args = parser.parse_args(argv)
    try:
        if args.scheduler and args.workers is not None:
            raise Error("--workers: the workers of a --scheduler are started on their machines "
                        "(dask-worker), not by this command")
        if args.threads is not None and not 0 <= args.threads <= 1024:
            raise Error("--threads: expected an integer in [0, 1024] (0 = all cores), got %d" %
                        args.threads)
        items = _parse_items(args.items) if args.items else None
        client = None
        if args.scheduler:
            from distributed import Client
            client = Client(args.scheduler)
        try:
            summary = run(args.spec, args.output, client, items=items, workers=args.workers,
                          threads=args.threads, items_per_task=args.items_per_task,
                          progress=False if (args.no_progress or args.quiet) else None,
                          quiet=args.quiet)
        finally:
            if client is not None:
                client.close()
    except (Error, OSError) as e:
        print("ringlet.batch: error: %s" % e, file=sys.stderr)
        return 1
    return 0 if summary.ok else 2


if __name__ == "__main__":
    # Run as the module ringlet.batch (not __main__), so that the tasks sent to the workers name
    # ringlet.batch._run_task, which the workers import.
    from ringlet.batch import main as _main
    sys.exit(_main())
