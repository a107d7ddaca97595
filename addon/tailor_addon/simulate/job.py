"""A bake of the scene's garment: build, run frames, write PC2 caches, attach Mesh Cache.

`BakeJob` is the Blender half of a bake: it gathers the arrays (`gather.py`), builds the
simulation (`core.simulate.build`) and hands frames to the bpy-free loop
(`tailor.bake.Bake`). The operator drives it either in one go (`execute`: headless, scripts)
or one frame per timer tick (`modal`: the UI, Esc cancels). Caches are written atomically
(`tailor.bake.write_pc2_atomic`) with every frame done so far when the bake ends, so a
cancelled bake leaves a playable cache and `resume` continues from its last frame. While it
runs, every `CHECKPOINT_S` seconds, the frames so far go to checkpoint files beside the caches
(`*.checkpoint.pc2`): a crash (or a kill on a render farm) loses at most the last seconds'
frames and Resume continues from the checkpoint, while the previous bake's caches, which the
scene plays, stay whole until the new bake ends.

Jobs stay in `JOBS` (per scene and garment) after they stop, so a resume in the same session
continues the very same solver state; otherwise the cached frames are solved again and
checked (`Bake.replay`) before the bake goes on.
"""

from __future__ import annotations

import hashlib
import json
import os
import time

import bpy
import numpy as np

import tailor
from tailor import bake

from .. import compat, preferences
from ..core import AddonError
from ..core import simulate as core_sim
from . import fit_map_attrs, gather

#: Live jobs by (scene, garment): the solver state a resume continues.
JOBS: dict[tuple[str, str], "BakeJob"] = {}

MODIFIER = "Tailor Cache"
#: Cached per-piece positions are local (float32): a replayed frame is compared with this tolerance.
REPLAY_ATOL = 1e-5


def cache_folder(scene) -> str:
    folder = preferences.cache_dir(scene)
    if folder.startswith("//") and not bpy.data.filepath:
        raise AddonError("the .blend is not saved, so the cache has no folder beside it",
                         "Save the file first, or set an absolute Cache Folder")
    return bpy.path.abspath(folder)


def frame_range(scene) -> tuple[int, int]:
    s = scene.tailor_simulate
    start, end = (scene.frame_start, scene.frame_end) if s.use_scene_range else (s.frame_start, s.frame_end)
    if end < start:
        raise tailor.InvalidParameterError(f"the frame range {start}-{end} is empty")
    return start, end


def _fingerprint(settings: core_sim.SimSettings, garment, colliders, start: int, preroll: str) -> str:
    h = hashlib.sha1()
    h.update(json.dumps(settings.__dict__, sort_keys=True, default=str).encode())
    h.update(np.ascontiguousarray(garment.positions).tobytes())
    for c in colliders:
        h.update(c.name.encode())
        h.update(np.ascontiguousarray(c.positions).tobytes())
    h.update(f"{start}/{preroll}".encode())
    return h.hexdigest()


#: Seconds of baking between two checkpoints (`BakeJob.checkpoint`): each rewrites every frame
#: done, so a long bake's checkpoints cost it a few per cent at most.
CHECKPOINT_S = 10.0


class BakeJob:
    """Everything a bake needs, gathered on the main thread at the start frame."""

    def __init__(self, scene):
        s = scene.tailor_simulate
        self.scene_name = scene.name
        self.key = (scene.name, s.garment)
        self.start, self.end = frame_range(scene)
        self.folder = cache_folder(scene)
        self.mode = s.cache_mode
        self.settings = gather.sim_settings(scene)
        garment, self.objects, fabrics, maps, self.collider_objects = gather.read_scene(scene)
        self.garment = garment
        self.piece_names = [o.name for o in self.objects]
        self.garment_name = s.garment or (self.objects[0].tailor_piece.garment or "garment")
        scene.frame_set(self.start)
        assembly = gather.rest_pose_positions(scene, self.collider_objects) if s.assemble_at_rest else None
        dg = bpy.context.evaluated_depsgraph_get()
        colliders = gather.collider_data(self.collider_objects, dg)
        if assembly is not None:  # the simulation starts where the assembly does
            for c, p in zip(colliders, assembly):
                c.positions = p
        built = core_sim.build(garment, self.settings, fabrics, maps, colliders)
        self.warnings = built.warnings
        self.adapter = built.adapter
        transition = s.transition if assembly is not None else 0
        self.fingerprint = _fingerprint(self.settings, garment, colliders, self.start, f"{s.preroll}/{transition}")
        gravity = bake.ASSEMBLY_GRAVITY if s.assemble_without_gravity else None
        self.fingerprint += f"/{gravity}"
        self.run = bake.Bake(built.sim, built.colliders, self.settings.fps, self.start, s.preroll, assembly, transition,
                             gravity, pins=built.pins)
        # With a Fit Map chosen, every frame's fit maps too (written beside the caches). The last
        # bake's maps describe the caches this bake replaces: forgotten now, so that the
        # frame-change handler does not write them at every frame the bake sets.
        self.run.keep_fit_maps = s.fit_map != "NONE"
        s.baked_fit_maps = ""
        # Piece transforms at the start: caches are in each piece's local space.
        self.inverse = [np.linalg.inv(np.array(o.matrix_world, np.float64)) for o in self.objects]
        # The last checkpoint: when, and how many frames it wrote.
        self.written = (time.monotonic(), 0)

    # ---- frames -------------------------------------------------------------------------------

    def colliders_at(self, frame: int) -> list[np.ndarray]:
        return gather.colliders_at(bpy.data.scenes[self.scene_name], self.collider_objects, frame)

    def step(self) -> dict:
        return self.run.step(self.colliders_at(self.run.next_frame))

    @property
    def done(self) -> bool:
        return self.run.next_frame > self.end

    # ---- caches -------------------------------------------------------------------------------

    def cache_paths(self) -> list[str]:
        stem = bpy.path.clean_name(self.garment_name)
        if self.mode == "GARMENT":
            return [os.path.join(self.folder, f"{stem}.pc2")]
        return [os.path.join(self.folder, f"{stem}__{bpy.path.clean_name(n)}.pc2") for n in self.piece_names]

    def local_frames(self, world: np.ndarray) -> list[np.ndarray]:
        """(frames, n, 3) world positions -> what each cache file stores."""
        if self.mode == "GARMENT":
            return [world]
        out = []
        for part, inv in zip(core_sim.split_pieces(world, self.garment.offsets, self.garment.num_particles),
                             self.inverse):
            out.append((part.astype(np.float64) @ inv[:3, :3].T + inv[:3, 3]).astype(np.float32))
        return out

    def checkpoint_paths(self) -> list[str]:
        return [os.path.splitext(p)[0] + ".checkpoint.pc2" for p in self.cache_paths()]

    def maps_path(self) -> str:
        return os.path.join(self.folder, f"{bpy.path.clean_name(self.garment_name)}.maps.npz")

    def report_path(self) -> str:
        return os.path.join(self.folder, f"{bpy.path.clean_name(self.garment_name)}.report.json")

    def write_frames(self, paths: list[str]) -> list[str]:
        """Every frame done into `paths` (the caches or the checkpoint), atomically."""
        os.makedirs(self.folder, exist_ok=True)
        for path, frames in zip(paths, self.local_frames(self.run.positions())):
            bake.write_pc2_atomic(path, frames, start_frame=self.start, sample_rate=1.0)
        return paths

    def write_caches(self) -> list[str]:
        """The caches with every frame done, and the quality report (as `tailor simulate` writes it)."""
        paths = self.write_frames(self.cache_paths())
        report = {
            "frames": self.run.records,
            "summary": self.run.summary(),
            "warnings": self.warnings,
            "thickness_m": self.settings.thickness,
            "adapter": self.adapter,
            "caches": [os.path.basename(p) for p in paths],
        }
        if self.run.fit_maps:
            fit_map_attrs.save_baked(self.maps_path(), self.run.fit_maps, self.piece_names, self.garment.offsets,
                                     self.garment.num_particles)
            report["fit_maps"] = os.path.basename(self.maps_path())
        tmp = self.report_path() + ".partial"
        with open(tmp, "w") as fh:
            json.dump(report, fh, indent=1)
        os.replace(tmp, self.report_path())
        for c in self.checkpoint_paths():  # the caches hold every frame now
            if os.path.isfile(c):
                os.remove(c)
        return paths

    def checkpoint(self) -> bool:
        """Writes every frame done to the checkpoint files, when `CHECKPOINT_S` seconds have
        passed since the last write and new frames were done; True when it wrote. Call it
        between frames (never while a solver thread adds one)."""
        at, count = self.written
        done = len(self.run.frames)
        if done == count or time.monotonic() - at < CHECKPOINT_S:
            return False
        self.write_frames(self.checkpoint_paths())
        self.written = (time.monotonic(), done)
        return True

    def read_cached(self) -> np.ndarray | None:
        """The frames already cached for this job, as world positions, or None: the checkpoint
        of a bake that stopped without ending (the latest frames solved), else the caches."""
        paths = self.checkpoint_paths()
        if not all(os.path.isfile(p) for p in paths):
            paths = self.cache_paths()
        if not all(os.path.isfile(p) for p in paths):
            return None
        parts = [tailor.read_pc2(p)["frames"] for p in paths]
        k = min(len(p) for p in parts)
        if self.mode == "GARMENT":
            return parts[0][:k]
        world = []
        for part, o in zip(parts, self.objects):
            m = np.array(o.matrix_world, np.float64)
            world.append((part[:k].astype(np.float64) @ m[:3, :3].T + m[:3, 3]).astype(np.float32))
        return np.concatenate(world, axis=1)

    def resume_from_cache(self, cancel=None) -> int:
        """Solves the cached frames again (checking them) so the bake can go on; returns how many."""
        cached = self.read_cached()
        if cached is None or len(cached) == 0:
            return 0
        cached = cached[: self.end - self.start + 1]
        self.run.replay(cached, self.colliders_at, cancel=cancel, atol=REPLAY_ATOL)
        return len(cached)

    def attach_caches(self, scene, paths: list[str]) -> None:
        """Mesh Cache modifiers playing the caches (on the pieces, or on a joined garment object)."""
        rel = [bpy.path.relpath(p) if bpy.data.filepath else p for p in paths]
        if self.mode == "GARMENT":
            targets = [self.garment_object(scene)]
        else:
            targets = [bpy.data.objects[n] for n in self.piece_names]
        for obj, path in zip(targets, rel):
            mod = obj.modifiers.get(MODIFIER) or obj.modifiers.new(MODIFIER, "MESH_CACHE")
            # First in the stack: later modifiers (Subdivision, Solidify) work on the cached shape.
            compat.move_modifier_first(obj, mod)
            mod.cache_format = "PC2"
            mod.filepath = path
            mod.play_mode = "SCENE"
            mod.time_mode = "FRAME"
            mod.frame_start = float(self.start)
            mod.frame_scale = 1.0
            mod.forward_axis = "POS_Y"
            mod.up_axis = "POS_Z"

    def garment_object(self, scene):
        """The joined garment (all pieces in world space, identity transform) for a per-garment cache."""
        name = f"{self.garment_name} (baked)"
        obj = bpy.data.objects.get(name)
        if obj is None:
            me = bpy.data.meshes.new(name)
            tris = self.garment.triangles.astype(np.int32)
            me.vertices.add(self.garment.num_particles)
            me.vertices.foreach_set("co", self.garment.positions.reshape(-1))
            me.loops.add(3 * len(tris))
            me.loops.foreach_set("vertex_index", tris.reshape(-1))
            me.polygons.add(len(tris))
            me.polygons.foreach_set("loop_start", np.arange(0, 3 * len(tris), 3, dtype=np.int32))
            if bpy.app.version < (4, 0, 0):
                me.polygons.foreach_set("loop_total", np.full(len(tris), 3, np.int32))
            me.update(calc_edges=True)
            obj = bpy.data.objects.new(name, me)
            scene.collection.objects.link(obj)
        return obj

    def summary_text(self) -> str:
        """The bake's summary in one line with its verdict (`tailor.bake.summary_text`)."""
        return bake.summary_text(self.run.summary())


def progress_line(rec: dict, done: int, total: int) -> str:
    """One frame of a bake as the log line a headless bake prints (`tailor simulate`'s figures)."""
    on_body = rec.get("on_body_fraction")
    return (f"Tailor: frame {rec['frame']} ({done}/{total}) {rec['ms']:.0f} ms, seam gap "
            f"{rec['seam_gap_max_m'] * 1e3:.2f} mm, penetrations {rec['penetration_count']}, "
            f"on body {'-' if on_body is None else f'{on_body * 100:.0f} %'}"
            + (", FAILED " + ", ".join(f["check"] for f in rec["failed"]) if rec.get("failed") else ""))


def finish(scene, job: BakeJob, cancelled: bool) -> str:
    """Ends a bake (done or cancelled): writes the caches and the report with every frame done,
    attaches the Mesh Cache modifiers, keeps a cancelled job for `resume`, puts the timeline
    back at the start frame. Returns the message for the status bar."""
    paths = job.write_caches() if job.run.frames else []
    if paths:
        job.attach_caches(scene, paths)
    s = scene.tailor_simulate
    s.baked_frames = len(job.run.frames)
    s.baked_fit_maps = job.maps_path() if job.run.fit_maps else ""
    s.bake_report = job.summary_text()
    scene.frame_set(job.start)
    if job.done:
        JOBS.pop(job.key, None)
    else:
        JOBS[job.key] = job
    verb = "Cancelled after" if cancelled else "Baked"
    where = os.path.dirname(paths[0]) if paths else "nowhere (no frame done)"
    return (f"{verb} frames {job.start}-{job.run.next_frame - 1} into {where}: {s.bake_report}"
            + (" (Resume continues)" if cancelled else ""))


def job_for(scene, resume: bool) -> tuple[BakeJob, int]:
    """The job to run and how many frames it resumed: a kept job when resuming and nothing
    changed, else a fresh one (re-solving the cache when resuming)."""
    frame = scene.frame_current
    try:
        fresh = BakeJob(scene)
    except BaseException:
        scene.frame_set(frame)  # nothing else was changed yet
        raise
    kept = JOBS.get(fresh.key)
    if resume and kept is not None and kept.fingerprint == fresh.fingerprint and kept.end <= fresh.end:
        kept.end = fresh.end
        return kept, len(kept.run.frames)
    if resume:
        return fresh, fresh.resume_from_cache()
    return fresh, 0
