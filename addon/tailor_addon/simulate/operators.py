"""Simulate operators: mark colliders, make a collider proxy, bake, live mode.

Every operator computes first (building the simulation validates the garment, the colliders
and the settings) and changes the scene after, so a bad setting is a report and the scene
stays as it was.
"""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, FloatProperty, IntProperty

from .. import scene_data
from ..core import AddonError
from ..core.errors import is_reportable
from ..core.simulate import triangle_size_spread
from ..reporting import report, reports_errors
from ..ui_common import redraw_view3d
from . import draw, gather, job as bake_job, live, runs


class TAILOR_OT_mark_collider(bpy.types.Operator):
    bl_idname = "tailor.mark_collider"
    bl_label = "Mark Collider"
    bl_description = "The garment collides with the selected meshes (evaluated with their modifiers every frame)"
    bl_options = {"REGISTER", "UNDO"}

    clear: BoolProperty(name="Clear", description="Unmark instead", default=False)

    @reports_errors("Marking colliders")
    def execute(self, context):
        objs = [o for o in context.selected_objects if o.type == "MESH" and not scene_data.is_piece(o)]
        if not objs:
            raise AddonError("no mesh other than garment pieces is selected", "Select the character's mesh")
        for o in objs:
            o.tailor_collider.is_collider = not self.clear
        self.report({"INFO"}, f"{'Unmarked' if self.clear else 'Marked'} {len(objs)} collider(s)")
        return {"FINISHED"}


class TAILOR_OT_collider_proxy(bpy.types.Operator):
    bl_idname = "tailor.collider_proxy"
    bl_label = "Make Collider Proxy"
    bl_description = (
        "An isotropic copy of the active mesh (voxel remesh) bound to it by Surface Deform, so it follows "
        "every frame; it becomes the collider and is hidden from render"
    )
    bl_options = {"REGISTER", "UNDO"}

    voxel_size: FloatProperty(name="Voxel Size", description="Edge length of the proxy", min=0.002, default=0.02,
                              subtype="DISTANCE", unit="LENGTH")
    offset: FloatProperty(
        name="Offset", description="Distance the proxy's vertices sit outside the mesh (the voxel remesh alone "
        "shrinks inside it by up to half a voxel)", min=0.0, default=0.001, subtype="DISTANCE", unit="LENGTH",
    )

    @classmethod
    def poll(cls, context):
        o = context.active_object
        return o is not None and o.type == "MESH"

    @reports_errors("Making the collider proxy")
    def execute(self, context):
        src = context.active_object
        if scene_data.is_piece(src):
            raise AddonError(f"'{src.name}' is a garment piece", "Make the proxy of the character")
        dg = context.evaluated_depsgraph_get()
        before = triangle_size_spread(gather.evaluated_positions(src, dg), gather.evaluated_triangles(src, dg))
        # The body as it is now (modifiers applied), remeshed by Blender's voxel remesher.
        base = bpy.data.meshes.new_from_object(src.evaluated_get(dg))
        proxy = bpy.data.objects.new(f"{src.name}_collider", base)
        proxy.matrix_world = src.matrix_world
        for coll in src.users_collection:
            coll.objects.link(proxy)
        try:
            rm = proxy.modifiers.new("Remesh", "REMESH")
            rm.mode = "VOXEL"
            rm.voxel_size = self.voxel_size
            # Back onto the surface: the voxel surface lies up to half a voxel inside the mesh
            # (measured on the sample body at 2 cm: 85 % of its vertices, up to 9.7 mm deep).
            sw = proxy.modifiers.new("Onto Surface", "SHRINKWRAP")
            sw.target = src
            sw.wrap_method = "NEAREST_SURFACEPOINT"
            sw.wrap_mode = "OUTSIDE_SURFACE"
            sw.offset = self.offset
            context.view_layer.update()
            dg = context.evaluated_depsgraph_get()
            remeshed = bpy.data.meshes.new_from_object(proxy.evaluated_get(dg))
            proxy.modifiers.remove(sw)
            proxy.modifiers.remove(rm)
            proxy.data = remeshed
            bpy.data.meshes.remove(base)
            if len(remeshed.polygons) == 0:
                raise AddonError(f"remeshing '{src.name}' at {self.voxel_size * 100:.3g} cm gave no faces",
                                 "Use a smaller voxel size, or a closed mesh")
            sd = proxy.modifiers.new("Follow " + src.name, "SURFACE_DEFORM")
            sd.target = src
            with context.temp_override(object=proxy, active_object=proxy):
                bpy.ops.object.surfacedeform_bind(modifier=sd.name)
            context.view_layer.update()
            if not sd.is_bound:
                raise AddonError(f"Surface Deform could not bind the proxy to '{src.name}'",
                                 "Check the mesh for loose or concave faces, or mark the mesh itself as collider")
        except BaseException:
            me = proxy.data
            bpy.data.objects.remove(proxy)
            if me.users == 0:
                bpy.data.meshes.remove(me)
            raise
        dg = context.evaluated_depsgraph_get()
        after = triangle_size_spread(gather.evaluated_positions(proxy, dg), gather.evaluated_triangles(proxy, dg))
        proxy.hide_render = True
        proxy.display_type = "WIRE"
        c = proxy.tailor_collider
        c.is_collider, c.proxy_of = True, src
        c.friction_static, c.friction_kinetic = src.tailor_collider.friction_static, src.tailor_collider.friction_kinetic
        c.spread_source_cv, c.spread_source_ratio = before["edge_cv"], before["edge_p95_p5"]
        c.spread_proxy_cv, c.spread_proxy_ratio = after["edge_cv"], after["edge_p95_p5"]
        src.tailor_collider.is_collider = False
        self.report({"INFO"}, f"Proxy '{proxy.name}': {after['triangles']} triangles; edge length spread "
                              f"(p95/p5) {before['edge_p95_p5']:.2f} -> {after['edge_p95_p5']:.2f}, "
                              f"CV {before['edge_cv']:.2f} -> {after['edge_cv']:.2f}")
        return {"FINISHED"}


class TAILOR_OT_bake(bpy.types.Operator):
    bl_idname = "tailor.bake"
    bl_label = "Bake"
    bl_description = (
        "Simulate the garment over the frame range into PC2 caches beside the .blend, played by Mesh Cache "
        "modifiers (Esc cancels, keeping the frames done)"
    )
    # No REGISTER: no Adjust Last Operation panel, whose redo would run the whole bake again.
    bl_options = {"UNDO"}

    resume: BoolProperty(name="Resume", description="Continue from the last cached frame", default=False)

    def _begin(self, context):
        live.stop(context.scene)
        job, resumed = bake_job.job_for(context.scene, self.resume)
        context.scene.tailor_simulate.adapter = job.adapter
        for w in job.warnings:
            self.report({"WARNING"}, w)
        return job, resumed

    @reports_errors("Baking")
    def execute(self, context):
        frame = context.scene.frame_current
        job, _ = self._begin(context)
        total = job.end - job.start + 1
        try:
            while not job.done:
                rec = job.step()
                # Headless (`blender -b ... bpy.ops.tailor.bake()`), a render farm's log is the
                # only progress there is: one line a frame.
                print(bake_job.progress_line(rec, len(job.run.frames), total), flush=True)
                job.checkpoint()
        except Exception:
            # The frames since the last checkpoint are dropped; the checkpoint stays (Resume).
            context.scene.frame_set(frame)
            raise
        self.report({"INFO"}, bake_job.finish(context.scene, job, cancelled=False))
        return {"FINISHED"}

    def invoke(self, context, event):
        try:
            job, _ = self._begin(context)
        except Exception as exc:
            if not is_reportable(exc):
                raise
            report(self, exc, "Baking")
            return {"CANCELLED"}
        # The solve runs on a native thread (`LiveSolver`: no Python thread in Blender); each
        # timer tick only collects what it finished, evaluates the colliders and hands them over.
        self._run = runs.BakeRun(context, job)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if self._run.job is None:  # ended by the load_pre handler, and then the file did not load
            self._run.cancel(context)
            return {"CANCELLED"}
        if event.type == "ESC":  # a job: Esc cancels it (reported, the frames done kept)
            return self._end(context, cancelled=True)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        try:
            if not self._run.tick(context):
                return {"RUNNING_MODAL"}
        except Exception as exc:
            self._end(context, cancelled=True)
            if not is_reportable(exc):
                raise
            report(self, exc, "Baking")
            return {"CANCELLED"}
        return self._end(context, cancelled=False)

    def cancel(self, context):
        self._run.cancel(context)

    def _end(self, context, cancelled: bool):
        # Cancelled: "Cancelled after frames ..., (Resume continues)", a warning in the status bar.
        self.report({"WARNING" if cancelled else "INFO"}, self._run.end(context, cancelled))
        return {"CANCELLED"} if cancelled else {"FINISHED"}


class TAILOR_OT_bake_clear(bpy.types.Operator):
    bl_idname = "tailor.bake_clear"
    bl_label = "Free Bake"
    bl_description = "Remove the Mesh Cache modifiers of the last bake (the cache files stay on disk)"
    bl_options = {"REGISTER", "UNDO"}

    @reports_errors("Freeing the bake")
    def execute(self, context):
        n = 0
        for o in context.scene.objects:
            mod = o.modifiers.get(bake_job.MODIFIER)
            if mod is not None:
                o.modifiers.remove(mod)
                n += 1
        bake_job.JOBS.clear()
        context.scene.tailor_simulate.baked_frames = 0
        self.report({"INFO"}, f"Removed {n} cache modifier(s)")
        return {"FINISHED"}


class TAILOR_OT_live(bpy.types.Operator):
    bl_idname = "tailor.live"
    bl_label = "Simulate Live"
    bl_description = (
        "The garment assembles and follows the character while the timeline plays or you scrub; edits to "
        "fabric, settings and pins apply at once (Stop Live ends it and restores the pieces)"
    )
    # No REGISTER: no redo panel re-running a simulation. Undo: it writes into the pieces' meshes.
    bl_options = {"UNDO"}

    def invoke(self, context, event):
        try:
            self._run = runs.LiveRun(context)
        except Exception as exc:
            if not is_reportable(exc):
                raise
            report(self, exc, "Starting Live mode")
            return {"CANCELLED"}
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        # Esc is not Live's: during playback it stops playback (Blender's convention); Live
        # ends with Stop Live (`tailor.live_stop`), which this sees as the session gone.
        session = self._run.session
        if session is None:
            self._run.end(context)
            return {"FINISHED"}
        if event.type == "TIMER":
            res = session.tick(context)
            if session.error is not None:
                report(self, session.error, "Live simulation")
                self._run.end(context)
                return {"FINISHED"}
            if res is not None:  # a new frame in the pieces (most ticks only find the solve running)
                redraw_view3d(context)
        return {"PASS_THROUGH"}

    def cancel(self, context):
        self._run.cancel(context)


class TAILOR_OT_live_step(bpy.types.Operator):
    bl_idname = "tailor.live_step"
    bl_label = "Live Step"
    bl_description = (
        "Live mode without the modal timer (scripts, tests): solve `count` frames off the main thread and "
        "apply each on the main thread, optionally advancing the timeline one frame each time"
    )
    bl_options = {"UNDO"}  # no redo panel: it would solve the frames again

    count: IntProperty(name="Frames", min=1, default=1)
    advance: BoolProperty(name="Advance Timeline", default=True)

    @reports_errors("Live simulation")
    def execute(self, context):
        scene = context.scene
        session = live.SESSIONS.get(scene.name) or live.start(context)
        for _ in range(self.count):
            if self.advance:
                scene.frame_set(scene.frame_current + 1)
            session.tick(context, block=True)
            if session.error is not None:
                err = session.error
                live.stop(scene)
                raise err
        return {"FINISHED"}


class TAILOR_OT_live_stop(bpy.types.Operator):
    bl_idname = "tailor.live_stop"
    bl_label = "Stop Live"
    bl_description = "Stop Live mode and put the pieces back as they were"
    # No redo panel: redone after an undo, the session it stopped is gone (Keep Shape would do nothing).
    bl_options = {"UNDO"}

    keep: BoolProperty(name="Keep Shape", description="Keep the simulated shape in the pieces", default=False)

    def execute(self, context):
        live.stop(context.scene, restore=not self.keep)
        draw.remove()
        return {"FINISHED"}


classes = (
    TAILOR_OT_mark_collider,
    TAILOR_OT_collider_proxy,
    TAILOR_OT_bake,
    TAILOR_OT_bake_clear,
    TAILOR_OT_live,
    TAILOR_OT_live_step,
    TAILOR_OT_live_stop,
)
