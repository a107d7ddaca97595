"""``tailor batch``: many bakes (garments x bodies x motions) on a Ray cluster or this machine.

    python -m tailor batch JOBS --out DIR [--address HOST:PORT] [--threads N] [--retries N]
        [--cpus N] [--log FILE.jsonl] [--retry-failed]

JOBS lists jobs or generates them (``tailor.batch.jobs``: the format); each job is one
``tailor simulate`` run, its report, cache and log in ``DIR/NAME/`` exactly as ``simulate``
would write them, and ``DIR/NAME/done.json`` last. ``--address`` joins a running Ray cluster;
without it a local Ray instance runs the jobs on this machine's cores (``--cpus``). Each job is
one Ray task of ``--threads`` CPUs (the solver's threads). A finished job is never redone; a
failing one is tried ``--retries`` more times, then recorded with its error. Progress on
standard error, every event in ``DIR/batch.jsonl``, a summary table at the end (and
``DIR/summary.json``).

Exit status: 0 when every job finished (the table gives each one's verdict), 1 when some job
failed all its tries, 2 on an error (a bad JOBS file, no Ray, no cluster at the address).
"""

from __future__ import annotations

import json
from pathlib import Path

#: Exit status when some job failed every try (the others finished).
FAILED_JOBS = 1


def register(sub):
    p = sub.add_parser("batch", help="run many simulations (garments x bodies x motions) on Ray")
    p.add_argument("jobs", metavar="JOBS", help="JSON (or .toml) file listing or generating the jobs")
    p.add_argument("--out", metavar="DIR", required=True, help="folder of the results: DIR/NAME/ per job")
    p.add_argument("--address", metavar="HOST:PORT",
                   help="join this Ray cluster (default: start a local Ray instance on this machine)")
    p.add_argument("--threads", type=int, default=1, metavar="N",
                   help="CPU threads of each job: its Ray task's CPUs and the solver's threads (default 1)")
    p.add_argument("--retries", type=int, default=2, metavar="N",
                   help="tries after the first of a job that fails (default 2)")
    p.add_argument("--cpus", type=int, metavar="N", help="CPUs of the local Ray instance (default: all cores)")
    p.add_argument("--log", metavar="FILE.jsonl", help="the JSON-lines event log (default DIR/batch.jsonl)")
    p.add_argument("--retry-failed", action="store_true",
                   help="run again the jobs an earlier batch recorded as failed (default: keep their error)")
    p.set_defaults(run=run)


def run(args) -> int:
    import tailor
    from tailor.batch import jobs as joblib
    from tailor.batch import runner

    for name, v in (("--threads", args.threads), ("--cpus", args.cpus)):
        if v is not None and v < 1:
            raise tailor.InvalidParameterError(f"{name} {v}: at least 1")
    if args.retries < 0:
        raise tailor.InvalidParameterError(f"--retries {args.retries}: at least 0")
    try:
        jobs = joblib.load(args.jobs)
    except joblib.JobsError as exc:
        raise tailor.InvalidParameterError(str(exc)) from None
    out = Path(args.out)
    try:
        rows = runner.run(jobs, out, address=args.address, threads=args.threads, retries=args.retries,
                          cpus=args.cpus, log_path=Path(args.log) if args.log else None,
                          retry_failed=args.retry_failed)
    except runner.BatchError as exc:
        raise tailor.TailorError(str(exc)) from None
    tmp = out / "summary.json"
    joblib.write_atomic(tmp, json.dumps(rows, indent=1).encode())
    print(runner.table(rows))
    return FAILED_JOBS if any(r["status"] == "failed" for r in rows) else 0
