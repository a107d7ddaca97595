"""The Simulate panel: colliders, settings, Live and Bake."""

from __future__ import annotations

import bpy

from .. import preferences, scene_data
from ..paint.maps import painted_maps
from ..ui_common import TailorPanel
from . import gather, live


class TAILOR_PT_simulate(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_simulate"
    bl_label = "Simulate"
    bl_order = 10

    def draw(self, context):
        layout = self.layout
        scene = context.scene
        s = scene.tailor_simulate
        # Live and Bake first: the actions.
        row = layout.row(align=True)
        if s.live_running and scene.name in live.SESSIONS:
            # Live's only stop (Esc stops playback, as everywhere in Blender).
            row.operator("tailor.live_stop", text="Stop Live", icon="PAUSE")
            st = live.SESSIONS[scene.name].stats()
            layout.label(text=f"{st['fps']:.1f} fps, seam gap {st['seam_gap_mm']:.2f} mm, "
                              f"{st['penetrations']} penetrations, strain {st['strain']:.3f}")
        else:
            row.operator("tailor.live", text="Simulate Live", icon="PLAY")
        layout.prop(s, "show_overlay")
        layout.prop(s, "fit_map")
        if s.fit_map != "NONE":
            layout.prop(s, "show_fit_map_overlay")
        layout.prop(s, "garment_choice")


class TAILOR_PT_simulate_colliders(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_simulate_colliders"
    bl_order = 11
    bl_label = "Colliders"
    bl_parent_id = "TAILOR_PT_simulate"

    def draw(self, context):
        layout = self.layout
        cols = gather.collider_objects(context.scene)
        if not cols:
            layout.label(text="No collider: select the character", icon="INFO")
        for o in cols:
            c = o.tailor_collider
            box = layout.box()
            box.label(text=o.name, icon="MOD_PHYSICS")
            if c.proxy_of is not None:
                box.label(text=f"Proxy of {c.proxy_of.name}: edge spread p95/p5 "
                               f"{c.spread_source_ratio:.2f} -> {c.spread_proxy_ratio:.2f}")
                box.label(text=f"edge length CV {c.spread_source_cv:.2f} -> {c.spread_proxy_cv:.2f}")
            row = box.row()
            row.prop(c, "friction_static", text="Static")
            row.prop(c, "friction_kinetic", text="Kinetic")
        row = layout.row(align=True)
        row.operator("tailor.mark_collider", icon="ADD")
        row.operator("tailor.mark_collider", text="Unmark", icon="REMOVE").clear = True
        layout.operator("tailor.collider_proxy", icon="MOD_REMESH")


class TAILOR_PT_simulate_settings(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_simulate_settings"
    bl_order = 12
    bl_label = "Settings"
    bl_parent_id = "TAILOR_PT_simulate"

    def draw(self, context):
        layout = self.layout
        s = context.scene.tailor_simulate
        layout.prop(s, "preset", expand=True)
        col = layout.column(align=True)
        col.prop(s, "substeps")
        col.prop(s, "iterations")
        col.prop(s, "tolerance")
        layout.prop(s, "two_level")
        layout.prop(s, "backend")
        if s.adapter:
            layout.label(text=f"Adapter: {s.adapter}", icon="MEMORY")
        # Gravity is the scene's (Scene Properties > Gravity), as Blender's own physics take it.
        row = layout.row(align=True)
        row.prop(context.scene, "use_gravity", text="Scene Gravity")
        sub = row.row(align=True)
        sub.active = context.scene.use_gravity
        sub.prop(context.scene, "gravity", text="")
        layout.prop(s, "air_damping")
        layout.prop(s, "ramp_enabled")
        col = layout.column(align=True)
        col.active = s.ramp_enabled
        col.prop(s, "ramp_closing_speed")
        col.prop(s, "ramp_closing_damping")
        layout.prop(s, "thickness")
        layout.prop(s, "self_collision")
        sub = layout.column()
        sub.active = s.self_collision
        sub.prop(s, "self_collision_contacts")
        sub.prop(s, "self_collision_radius")
        col = layout.column(align=True)
        col.prop(s, "seam_stiffness")
        col.prop(s, "seam_bend_stiffness")
        col.label(text=f"{len(context.scene.tailor.seams)} seams: per-seam factors in the Seams panel")
        row = layout.row(align=True)
        row.prop(s, "friction_static")
        row.prop(s, "friction_kinetic")
        row = layout.row(align=True)
        row.prop(s, "pin_mode", text="Pins")
        sub = row.row(align=True)
        sub.active = s.pin_mode == "ATTACH"
        sub.prop(s, "pin_stiffness", text="N/m")
        obj = context.active_object
        if scene_data.is_piece(obj):
            box = layout.box()
            box.label(text=f"Fabric of {obj.name}", icon="MOD_CLOTH")
            p = obj.tailor_piece
            box.prop(p, "fabric", text="")
            for name in ("density", "stretch", "shear", "bend", "anisotropic"):
                box.prop(p, name)
            if p.anisotropic:
                for name in ("stretch_v", "bend_bias", "bend_v"):
                    box.prop(p, name)
            maps = painted_maps(obj)
            box.label(text="Painted: " + (", ".join(sorted(maps)) if maps else "nothing (Paint panel)"))


class TAILOR_PT_simulate_bake(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_simulate_bake"
    bl_order = 13
    bl_label = "Bake"
    bl_parent_id = "TAILOR_PT_simulate"

    def draw(self, context):
        layout = self.layout
        s = context.scene.tailor_simulate
        layout.prop(s, "use_scene_range")
        row = layout.row(align=True)
        row.active = not s.use_scene_range
        row.prop(s, "frame_start")
        row.prop(s, "frame_end")
        layout.prop(s, "preroll")
        layout.prop(s, "cache_dir")
        if not s.cache_dir:
            layout.label(text=f"Preferences' folder: {preferences.cache_dir(context.scene)}", icon="PREFERENCES")
        layout.prop(s, "cache_mode", expand=True)
        row = layout.row(align=True)
        row.operator("tailor.bake", icon="RENDER_ANIMATION")
        row.operator("tailor.bake", text="Resume", icon="FORWARD").resume = True
        layout.operator("tailor.bake_clear", icon="TRASH")
        row = layout.row(align=True)
        row.operator("tailor.export_welded", text="Welded Mesh", icon="AUTOMERGE_ON")
        row.operator("tailor.export_welded", text="Welded OBJ…", icon="EXPORT").export_format = "OBJ"
        row.operator("tailor.export_welded", text="glTF…", icon="EXPORT").export_format = "GLB"
        row = layout.row(align=True)
        row.enabled = bool(s.baked_frames)
        row.operator("tailor.export_animation", text="Alembic…", icon="EXPORT").export_format = "ABC"
        row.operator("tailor.export_animation", text="USD…", icon="EXPORT").export_format = "USD"
        if s.baked_frames:
            layout.label(text=s.bake_report, icon="INFO")


classes = (TAILOR_PT_simulate, TAILOR_PT_simulate_colliders, TAILOR_PT_simulate_settings, TAILOR_PT_simulate_bake)
