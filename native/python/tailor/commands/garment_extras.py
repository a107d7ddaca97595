"""The parts of a garment file that `tailor.Garment` does not set or return yet.

A garment file (`NAME.json` manifest + `NAME.bin` sidecar, `tailor_core::garment_file`) has room
for free-form named settings (the manifest's `settings` object) and for painted per-particle
parameters (arrays in the sidecar, listed in the manifest's `particle_params`). `tailor.Garment`
saves and loads them intact and returns them (`Garment.settings_json`, `.particle_params`) but
does not set them, so the sample garments (per-piece fabric, collision levels) write them here
after `Garment.save`, and `read_extras` reads them back through `Garment.load`. The
encoding mirrors `garment_file/codec.rs`: arrays little-endian, each at a multiple of 8 bytes
after the 8-byte magic, the sidecar's size and FNV-1a 64-bit hash recorded in the manifest;
`tailor.Garment.load` checks all of it, so a file written here that loads there is well formed.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

MAGIC = b"TLRBIN\x00\x01"
DTYPES = {"f32": np.dtype("<f4"), "i32": np.dtype("<i4"), "bool": np.dtype("u1")}


def fnv1a64(data: bytes) -> int:
    """FNV-1a, 64 bit, as codec.rs computes it (sidecars are small: a plain loop will do)."""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def _dtype_name(values: np.ndarray) -> str:
    if values.dtype == np.bool_:
        return "bool"
    if np.issubdtype(values.dtype, np.integer):
        return "i32"
    return "f32"


def add_extras(
    manifest: str | os.PathLike,
    settings: dict[str, Any] | None = None,
    params: list[tuple[str, int, np.ndarray]] | None = None,
) -> None:
    """Adds named `settings` (JSON values) and per-particle `params` ((name, piece, values), one
    value per vertex of that piece's mesh) to a garment file written by `Garment.save`."""
    manifest = Path(manifest)
    head = json.loads(manifest.read_text())
    side = manifest.parent / head["sidecar"]["file"]
    bin_ = bytearray(side.read_bytes())
    if bin_[: len(MAGIC)] != MAGIC:
        raise ValueError(f"{side}: not a Tailor garment sidecar")
    for name, piece, values in params or []:
        values = np.asarray(values)
        kind = _dtype_name(values)
        while len(bin_) % 8:
            bin_.append(0)
        offset = len(bin_)
        bin_ += np.ascontiguousarray(values, DTYPES[kind]).tobytes()
        head["particle_params"].append(
            {"name": name, "piece": int(piece), "dtype": kind, "offset": offset, "count": int(len(values))}
        )
    head["settings"].update(settings or {})
    head["sidecar"]["bytes"] = len(bin_)
    head["sidecar"]["fnv1a64"] = f"{fnv1a64(bytes(bin_)):016x}"
    # Sidecar first, as garment_file::save does: the manifest always points at a complete one.
    side.write_bytes(bytes(bin_))
    manifest.write_text(json.dumps(head, indent=2))


def read_extras(manifest: str | os.PathLike) -> tuple[dict[str, Any], dict[str, dict[int, np.ndarray]]]:
    """The named settings and the per-particle params ({name: {piece: values}}) of a garment
    file, read by `tailor.Garment.load` (which checks the sidecar's place, size and hash:
    reading it again here by hand once followed a symbolic link to /dev/zero)."""
    import tailor

    garment = tailor.Garment.load(manifest)
    params: dict[str, dict[int, np.ndarray]] = {}
    for name, piece, values in garment.particle_params:
        params.setdefault(name, {})[int(piece)] = np.asarray(values)
    return dict(json.loads(garment.settings_json)), params


def encode_runs(values: np.ndarray) -> list[list[int]]:
    """Run-length encoding [[start, length, value], ...] of the non-zero runs of an int array
    (collider levels are painted in large regions: compact in a JSON manifest)."""
    v = np.asarray(values, np.int64)
    if len(v) == 0:
        return []
    change = np.flatnonzero(np.diff(v)) + 1
    starts = np.concatenate([[0], change])
    lengths = np.diff(np.concatenate([starts, [len(v)]]))
    return [[int(s), int(n), int(v[s])] for s, n in zip(starts, lengths) if v[s] != 0]


def decode_runs(runs: list[list[int]], n: int) -> np.ndarray:
    """Inverse of `encode_runs`, as int64 so that no value wraps (2**32 + 1 became 1 in an
    int32 array); the levels' range is checked where they are set (`set_collider_levels`).
    Runs outside the `n` values, or that are not [start, length, value] integers, are refused."""
    import tailor

    out = np.zeros(n, np.int64)
    for run in runs:
        if not (isinstance(run, (list, tuple)) and len(run) == 3 and all(isinstance(x, int) for x in run)):
            raise tailor.InvalidParameterError(f"collider level run {run!r}: expected [start, length, value] integers")
        s, length, value = run
        if s < 0 or length < 0 or s + length > n:
            raise tailor.InvalidParameterError(f"collider level run {run!r} lies outside the mesh's {n} vertices")
        out[s : s + length] = value
    return out
