"""One ``tailor batch`` job, where it runs (a Ray worker, or any process): exactly what
``tailor simulate`` would do for it, through the command line's own parser and ``run`` function
(and ``tailor import``'s first for a pattern), in a private temporary folder.

The job's input files come as bytes and its outputs go back as bytes: a worker on another machine
needs no shared file system, and the driver alone writes into the batch's folder (atomically,
``tailor.batch.jobs.write_done``). Nothing here imports Ray.
"""

from __future__ import annotations

import contextlib
import io
import os
import socket
import tempfile
import time
from pathlib import Path

from tailor.batch import jobs as joblib


def execute(job: dict, names: list[tuple[str, str]], blobs: list[bytes], threads: int | None) -> dict:
    """Runs `job` given its inputs (`names`: (role, file name) for each of `blobs`, as
    ``jobs.inputs`` lists them) on `threads` solver threads. Returns {"ok": True, "exit": the
    simulate command's exit status, "files": {path in the job's folder: bytes}, ...} or
    {"ok": False, "error": one line, ...}; never raises for the job's own errors (the driver
    decides about retries), so an exception out of here is the worker's, not the job's."""
    from tailor import cli

    started = time.time()
    log = io.StringIO()
    where = {"host": socket.gethostname(), "pid": os.getpid(), "node": _ray_node()}
    with tempfile.TemporaryDirectory(prefix="tailor-batch-") as tmp:
        root = Path(tmp)
        paths: dict[str, str] = {}
        for (role, name), data in zip(names, blobs):
            # Each role in its own folder under its own file name: a garment file finds its sidecar
            # beside it, and the garment's name (USD prim, OBJ files) is the original's.
            folder = root / "in" / ("garment" if role == "sidecar" else role)
            folder.mkdir(parents=True, exist_ok=True)
            (folder / name).write_bytes(data)
            paths[role] = str(folder / name)
        out = root / "out"
        out.mkdir()
        command = "import" if job["kind"] == "pattern" else "simulate"
        try:
            with contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
                if job["kind"] == "pattern":
                    garment = str(out / joblib.OUTPUTS["garment"] / (Path(paths["pattern"]).stem + ".json"))
                    Path(garment).parent.mkdir()
                    args = joblib.parse(joblib.import_argv(job, paths["pattern"], garment))
                    args.run(args)
                else:
                    garment = paths["garment"]
                command = "simulate"
                args = joblib.parse(joblib.simulate_argv(job, garment, paths["collider"], paths.get("collider_anim"),
                                                         str(out), threads))
                status = int(args.run(args) or 0)
        except Exception as exc:  # noqa: BLE001 - the job failed; its error goes back as one line
            # The job's files by their own names, not the private folder's (it is gone by now).
            error = f"tailor {command}: error: {cli._one_line(exc)}"
            for role, path in paths.items():
                error = error.replace(path, os.path.basename(path))
            if not isinstance(exc, (OSError, ValueError, RuntimeError)):
                error += f" ({type(exc).__name__})"
            return {"ok": False, "error": error, "log": log.getvalue(), "seconds": time.time() - started, **where}
        files = {}
        for p in sorted(out.rglob("*")):
            if p.is_file():
                rel = p.relative_to(out).as_posix()
                if job["kind"] == "pattern" and rel.startswith(joblib.OUTPUTS["garment"] + "/") \
                        and "garment" not in job["outputs"]:
                    continue  # the imported garment was only a step, not an output asked for
                files[rel] = p.read_bytes()
    # The log names the job's files by their names in its folder, not the private folder's.
    text = log.getvalue().replace(str(out) + os.sep, "")
    for path in paths.values():
        text = text.replace(path, os.path.basename(path))
    files[joblib.LOG] = text.encode()
    return {"ok": True, "exit": status, "files": files, "seconds": time.time() - started, **where}


def _ray_node() -> str | None:
    """The Ray node this runs on (its id), None outside Ray."""
    import sys

    ray = sys.modules.get("ray")  # only when the job runs inside Ray: no import of it otherwise
    try:
        if ray is not None and ray.is_initialized():
            return ray.get_runtime_context().get_node_id()
    except Exception:  # noqa: BLE001 - only a label for the log
        pass
    return None
