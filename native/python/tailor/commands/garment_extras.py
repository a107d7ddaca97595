"""The parts of a garment file that `tailor.Garment` does not set or return yet.

A garment file (`NAME.json` manifest + `NAME.bin` sidecar, `tailor_core::garment_file`) has room
for free-form named settings (the manifest's `settings` object) and for painted per-particle
parameters (arrays in the sidecar, listed in the manifest's `particle_params`). `tailor.Garment`
saves and loads them intact but exposes neither, so the sample garments (per-piece fabric,
collision levels) write them here after `Garment.save`, and the demo reads them back. The
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
    """(settings, {param name: {piece: values}}) of a garment file."""
    manifest = Path(manifest)
    head = json.loads(manifest.read_text())
    bin_ = (manifest.parent / head["sidecar"]["file"]).read_bytes()
    params: dict[str, dict[int, np.ndarray]] = {}
    for r in head.get("particle_params", []):
        dt = DTYPES[r["dtype"]]
        a = np.frombuffer(bin_, dt, count=int(r["count"]), offset=int(r["offset"]))
        params.setdefault(r["name"], {})[int(r["piece"])] = a.astype(bool) if r["dtype"] == "bool" else a.copy()
    return dict(head.get("settings", {})), params


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
    out = np.zeros(n, np.int32)
    for s, length, value in runs:
        out[s : s + length] = value
    return out
