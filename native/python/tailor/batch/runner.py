"""``tailor batch``'s jobs on Ray: one task per job, results written as they finish.

Ray is imported here, when a batch has work to do, and nowhere else in the package (the wheel in
the Blender add-on does not depend on it). ``address`` joins a running cluster (``ray start``, or
one of Ray's launchers); without it the same code starts a local Ray instance on this machine's
cores and stops it at the end.

What never gets lost:
- a job whose folder holds a matching done marker (``tailor.batch.jobs.is_done``) is skipped, so a
  killed batch resumes where it stopped and a batch run twice does nothing the second time;
- a job that fails (its error, or its worker's death after Ray's own retries) is submitted again
  up to ``retries`` more times, then recorded with its error (``failed.json``) while the others
  go on; a rerun skips it too unless ``retry_failed``;
- a worker or node that dies mid-job: Ray reschedules the task (``max_retries``, system failures
  only) on a node still alive;
- the driver alone writes into the batch's folder, each file atomically and the marker last.

Progress: a line for people on standard error (a bar that redraws on a terminal, a line per
finished job otherwise) with jobs done, failed, running and the time left, and every event as
one JSON object a line in the log (``DIR/batch.jsonl`` by default).
"""

from __future__ import annotations

import json
import os
import sys
import time
from datetime import datetime, timezone
from pathlib import Path
from typing import TextIO

from tailor.batch import jobs as joblib

#: Ray's own retries of a task whose worker or node died (system failures; a job's own errors
#: are retried by the driver, ``retries`` times).
NODE_RETRIES = 4

NEEDS_RAY = "tailor batch needs Ray: pip install ray"


class BatchError(RuntimeError):
    """A batch that cannot start (no Ray, no cluster at the address); one line."""


def _task(job: dict, names: list, threads: int | None, *blobs: bytes) -> dict:
    """The Ray task of one job (the blobs, ObjectRefs when submitted, arrive as bytes)."""
    from tailor.batch.execute import execute

    return execute(job, names, list(blobs), threads)


class EventLog:
    """The JSON-lines log: one object a line, appended and flushed as each event happens."""

    def __init__(self, path: Path):
        path.parent.mkdir(parents=True, exist_ok=True)
        self.fh = open(path, "a", buffering=1)
        self.t0 = time.time()

    def __call__(self, event: str, **fields) -> None:
        doc = {"time": datetime.now(timezone.utc).isoformat(timespec="milliseconds"),
               "elapsed_s": round(time.time() - self.t0, 3), "event": event, **fields}
        self.fh.write(json.dumps(doc) + "\n")

    def close(self) -> None:
        self.fh.close()


class Progress:
    """Jobs done, failed, running and the estimated time left, on `stream`: a bar redrawn in place
    on a terminal, one line per change otherwise (a log file, a CI job)."""

    def __init__(self, total: int, stream: TextIO, skipped: int = 0):
        self.total, self.stream, self.skipped = total, stream, skipped
        self.done = self.failed = self.running = 0
        self.t0 = time.time()
        self.tty = stream.isatty()
        self.last = ""

    def eta(self) -> str:
        finished = self.done + self.failed
        left = self.total - finished
        if not finished:
            return "?"
        s = int(round((time.time() - self.t0) / finished * left))
        return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"

    def show(self, final: bool = False) -> None:
        finished = self.done + self.failed
        width = 24
        fill = int(width * finished / self.total) if self.total else width
        line = (f"[{'#' * fill}{'.' * (width - fill)}] {finished}/{self.total} jobs: {self.done} done, "
                f"{self.failed} failed, {self.running} running"
                + (f", {self.skipped} already done" if self.skipped else "") + f", {self.eta()} left")
        if line == self.last and not final:
            return
        self.last = line
        if self.tty:
            self.stream.write("\r" + line + ("\n" if final else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _report_summary(files: dict) -> dict | None:
    try:
        return json.loads(files[joblib.REPORT])["summary"]
    except (KeyError, ValueError):
        return None


def run(jobs: list[dict], out: Path, *, address: str | None = None, threads: int = 1, retries: int = 2,
        cpus: int | None = None, log_path: Path | None = None, retry_failed: bool = False,
        stream: TextIO = sys.stderr) -> list[dict]:
    """Runs the jobs not done yet; returns one row per job (name, status, attempts, exit, seconds,
    node, summary, error) in the jobs' order, for the summary table."""
    out.mkdir(parents=True, exist_ok=True)
    log = EventLog(log_path or out / "batch.jsonl")
    try:
        return _run(jobs, out, log, address=address, threads=threads, retries=retries, cpus=cpus,
                    retry_failed=retry_failed, stream=stream)
    finally:
        log.close()


def _run(jobs, out, log, *, address, threads, retries, cpus, retry_failed, stream) -> list[dict]:
    rows: dict[str, dict] = {}
    todo = []
    for job in jobs:
        folder = out / job["name"]
        digest = joblib.job_hash(job)
        done = joblib.is_done(folder, digest)
        failed = None if retry_failed else joblib.read_marker(folder, joblib.FAILED)
        if done:
            rows[job["name"]] = {"name": job["name"], "status": "done", "skipped": True, **_row_fields(done)}
        elif failed and failed.get("hash") == digest:
            rows[job["name"]] = {"name": job["name"], "status": "failed", "skipped": True, **_row_fields(failed)}
        else:
            todo.append((job, digest))
    skipped = len(jobs) - len(todo)
    log("batch", jobs=len(jobs), to_run=len(todo), skipped=skipped, address=address, threads=threads,
        retries=retries)
    for name, row in rows.items():
        log("skip", job=name, status=row["status"])
    if todo:
        _on_ray(todo, out, log, rows, address=address, threads=threads, retries=retries, cpus=cpus,
                stream=stream, skipped=skipped)
    else:
        stream.write(f"tailor batch: all {len(jobs)} jobs already done (nothing to run)\n")
    ordered = [rows[j["name"]] for j in jobs if j["name"] in rows]
    log("end", done=sum(r["status"] == "done" for r in ordered), failed=sum(r["status"] == "failed" for r in ordered))
    return ordered


def _row_fields(marker: dict) -> dict:
    return {k: marker.get(k) for k in ("attempts", "exit", "seconds", "node", "summary", "error")}


def _start_ray(address, cpus):
    try:
        import ray
    except ImportError:
        raise BatchError(NEEDS_RAY) from None
    import logging

    # Ray's own start-up chatter stays out of the command's output; its warnings still show.
    kwargs = dict(include_dashboard=False, logging_level=logging.WARNING, log_to_driver=False)
    try:
        if address:
            ray.init(address=address, **kwargs)
        else:
            # "local": a new instance of its own, even where `ray start` runs a cluster on this
            # machine (plain ray.init() would join that one).
            ray.init(address="local", num_cpus=cpus or os.cpu_count(), **kwargs)
    except (ConnectionError, RuntimeError, ValueError) as exc:
        raise BatchError(f"cannot {'join the Ray cluster at ' + address if address else 'start a local Ray'}: "
                         f"{_one_line(exc)}") from None
    return ray


def _on_ray(todo, out, log, rows, *, address, threads, retries, cpus, stream, skipped):
    ray = _start_ray(address, cpus)
    try:
        remote = ray.remote(_task).options(num_cpus=threads, max_retries=NODE_RETRIES, retry_exceptions=False)
        # Each input file goes into Ray's object store once, however many jobs read it.
        blobs: dict[str, object] = {}
        for job, _ in todo:
            for _, path in joblib.inputs(job):
                if path not in blobs:
                    blobs[path] = ray.put(Path(path).read_bytes())

        def submit(job, attempt):
            files = joblib.inputs(job)
            names = [(role, os.path.basename(p)) for role, p in files]
            ref = remote.remote(job, names, threads, *[blobs[p] for _, p in files])
            log("submit", job=job["name"], attempt=attempt)
            return ref

        inflight = {}
        for job, digest in todo:
            inflight[submit(job, 1)] = (job, digest, 1)

        def slots():
            # Jobs that can run at once: the cluster's CPUs (as they are now: nodes come and go)
            # over the threads of each.
            return max(1, int(ray.cluster_resources().get("CPU", 1) // threads))

        progress = Progress(len(todo), stream, skipped)
        n_slots, slots_at = slots(), time.time()
        while inflight:
            if time.time() - slots_at > 5:
                n_slots, slots_at = slots(), time.time()
            progress.running = min(len(inflight), n_slots)
            progress.show()
            ready, _ = ray.wait(list(inflight), num_returns=1, timeout=1.0)
            for ref in ready:
                job, digest, attempt = inflight.pop(ref)
                try:
                    result = ray.get(ref)
                except ray.exceptions.RayError as exc:
                    # The worker or its node died more often than Ray retries, or the task could
                    # not run at all: the job's try failed, the driver decides what next.
                    result = {"ok": False, "error": f"{type(exc).__name__}: {_one_line(exc)[:500]}"}
                folder = out / job["name"]
                if result["ok"]:
                    marker = joblib.write_done(folder, digest, result["files"], {
                        "name": job["name"], "status": "done", "attempts": attempt, "exit": result["exit"],
                        "seconds": result["seconds"], "node": result.get("node"), "host": result.get("host"),
                        "summary": _report_summary(result["files"])})
                    rows[job["name"]] = {"name": job["name"], "status": "done", "skipped": False,
                                         **_row_fields(marker)}
                    progress.done += 1
                    summary = marker["summary"] or {}
                    log("done", job=job["name"], attempt=attempt, exit=result["exit"],
                        seconds=round(result["seconds"], 3), node=result.get("node"), host=result.get("host"),
                        pid=result.get("pid"), verdict=[v["check"] for v in summary.get("verdict", [])])
                elif attempt <= retries:
                    log("retry", job=job["name"], attempt=attempt, error=result["error"], node=result.get("node"))
                    inflight[submit(job, attempt + 1)] = (job, digest, attempt + 1)
                else:
                    if result.get("log"):
                        joblib.write_atomic(folder / joblib.LOG, result["log"].encode())
                    marker = joblib.write_failed(folder, digest, {
                        "name": job["name"], "status": "failed", "attempts": attempt, "error": result["error"],
                        "node": result.get("node")})
                    rows[job["name"]] = {"name": job["name"], "status": "failed", "skipped": False,
                                         **_row_fields(marker)}
                    progress.failed += 1
                    log("failed", job=job["name"], attempts=attempt, error=result["error"], node=result.get("node"))
        progress.running = 0
        progress.show(final=True)
    finally:
        ray.shutdown()


def table(rows: list[dict]) -> str:
    """The summary table: one line per job with its status, tries, time and quality figures
    (the report's summary: worst case over its frames) and its verdict, or its error."""
    head = (f"{'job':<32} {'status':<7} {'tries':>5} {'s':>6} {'frames':>6} {'ms/frame':>8} {'gap mm':>7} "
            f"{'pen mm':>7} {'strain':>6} {'on body':>7}  verdict")
    lines = [head, "-" * len(head)]
    for r in rows:
        s = r.get("summary") or {}
        tries = r.get("attempts") or "-"
        secs = f"{r['seconds']:.1f}" if r.get("seconds") is not None else "-"
        name = r["name"] + (" *" if r.get("skipped") else "")
        if r["status"] != "done":
            lines.append(f"{name:<32} {'FAILED':<7} {tries:>5} {secs:>6}  {r.get('error') or ''}")
            continue
        share = s.get("on_body_fraction")
        verdict = ", ".join(f"{v['check']} (frame {v['frame']})" for v in s.get("verdict", [])) or "passes"
        if s.get("nan"):
            verdict = "NaN; " + verdict
        lines.append(f"{name:<32} {'done':<7} {tries:>5} {secs:>6} {s.get('frame', 0):>6} {s.get('ms', 0):>8.1f} "
                     f"{s.get('seam_gap_max_m', 0) * 1e3:>7.2f} {s.get('penetration_max_m', 0) * 1e3:>7.2f} "
                     f"{s.get('strain_max', 0):>6.3f} {'-' if share is None else f'{share * 100:.0f} %':>7}  {verdict}")
    if any(r.get("skipped") for r in rows):
        lines.append("* already done (or failed) in an earlier run with the same inputs: not run again")
    return "\n".join(lines)
