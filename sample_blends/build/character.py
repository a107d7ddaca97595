"""Builds the sample character: sample_blends/character.blend and sample_blends/character.glb.

    .venv/bin/python sample_blends/build/character.py [--render out/character [--docs-img docs/img]]

Stages, in order:

1. the GarmentCode mean body (sources/mean_all.obj, Y-up) is read and turned Z-up (body_joints);
2. an armature is fitted to it from joints measured on the mesh (body_joints.find_joints);
3. the body is skinned with Blender's automatic (bone heat) weights, then limited to the 4
   strongest bones per vertex and normalised, so Blender and any glTF reader (4 joints per
   vertex) deform it identically;
4. a walk and a run (motions.py) are keyed on every frame as two named actions, each also on
   its own NLA track so that glTF export writes both; the walk is the active action;
5. camera, light, metric units and a Workbench look; the .blend is saved;
6. the armature and body are exported as a binary glTF with its skin and both animations, for
   the headless module (`tailor.AnimatedMesh`);
7. with --render, contact sheets of each action are rendered with Workbench into that folder
   (and with --docs-img, the small preview strips of the docs).

Needs the `bpy` wheel: `.venv/bin/pip install "bpy==4.5.*"` (Python 3.11).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SAMPLES = HERE.parent
sys.path.insert(0, str(HERE))

try:
    import bpy
    from mathutils import Matrix, Quaternion, Vector
except ImportError:
    sys.exit('character.py needs the bpy wheel: .venv/bin/pip install "bpy==4.5.*" (Python 3.11)')

import numpy as np

import body_joints
import motions

SOURCE = SAMPLES / "sources" / "mean_all.obj"
FPS = 30
ACTIONS = (("walk", motions.WALK), ("run", motions.RUN))


def build_body(verts: np.ndarray, tris: np.ndarray) -> bpy.types.Object:
    mesh = bpy.data.meshes.new("Body")
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.astype(np.float32).ravel())
    mesh.loops.add(tris.size)
    mesh.loops.foreach_set("vertex_index", tris.astype(np.int32).ravel())
    mesh.polygons.add(len(tris))
    mesh.polygons.foreach_set("loop_start", np.arange(0, tris.size, 3, dtype=np.int32))
    mesh.update()
    mesh.validate()
    mesh.shade_smooth()
    mat = bpy.data.materials.new("Skin")
    mat.diffuse_color = (0.80, 0.62, 0.52, 1.0)
    mesh.materials.append(mat)
    obj = bpy.data.objects.new("Body", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build_armature(joints: dict[str, np.ndarray]) -> bpy.types.Object:
    arm = bpy.data.armatures.new("Rig")
    obj = bpy.data.objects.new("Rig", arm)
    bpy.context.scene.collection.objects.link(obj)
    obj.show_in_front = True
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    for b in motions.skeleton():
        eb = arm.edit_bones.new(b.name)
        eb.head, eb.tail = Vector(joints[b.head]), Vector(joints[b.tail])
        # Roll: local Z towards the front for every bone, so rotations read alike in the UI.
        eb.align_roll(Vector(motions.FORWARD))
        if b.parent:
            eb.parent = arm.edit_bones[b.parent]
            eb.use_connect = (eb.parent.tail - eb.head).length < 1e-6
    bpy.ops.object.mode_set(mode="OBJECT")
    return obj


def skin(body: bpy.types.Object, rig: bpy.types.Object) -> int:
    """Automatic weights; returns how many vertices got none (bone heat's failure mode)."""
    bpy.ops.object.select_all(action="DESELECT")
    body.select_set(True)
    rig.select_set(True)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    bpy.context.view_layer.objects.active = body
    bpy.ops.object.vertex_group_limit_total(group_select_mode="ALL", limit=4)
    bpy.ops.object.vertex_group_normalize_all(group_select_mode="ALL", lock_active=False)
    return sum(1 for v in body.data.vertices if not any(g.weight > 0 for g in v.groups))


def key_action(rig: bpy.types.Object, name: str, poses) -> bpy.types.Action:
    """Keys every frame of `poses` (motions.frames) as the action `name`, starting at frame 1."""
    rig.animation_data_create()
    action = bpy.data.actions.new(name)
    action.use_fake_user = True
    rig.animation_data.action = action
    rest = {b.name: b.matrix_local.to_3x3() for b in rig.data.bones}
    prev: dict[str, Quaternion] = {}
    for i, (root, R) in enumerate(poses):
        frame = 1 + i
        for pb in rig.pose.bones:
            B = rest[pb.name]
            q = (B.inverted() @ Matrix(R[pb.name].tolist()) @ B).to_quaternion()
            if pb.name in prev:
                q.make_compatible(prev[pb.name])
            prev[pb.name] = q
            pb.rotation_mode = "QUATERNION"
            pb.rotation_quaternion = q
            pb.keyframe_insert("rotation_quaternion", frame=frame, group=pb.name)
            if pb.parent is None:
                pb.location = B.inverted() @ Vector(root)
                pb.keyframe_insert("location", frame=frame, group=pb.name)
    action.use_frame_range = True
    action.frame_range = (1, len(poses))
    action.use_cyclic = True
    return action


def stage(rig: bpy.types.Object, actions: dict[str, bpy.types.Action]):
    scene = bpy.context.scene
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    scene.render.fps = FPS
    for name, action in actions.items():
        track = rig.animation_data.nla_tracks.new()
        track.name = name
        track.strips.new(name, 1, action)
        track.mute = True  # the active action plays; the tracks keep the others for export
    rig.animation_data.action = actions["walk"]
    scene.frame_start, scene.frame_end = 1, motions.WALK.frames  # frame 33 = frame 1: loops
    scene.frame_set(1)

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 50
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (2.6, -4.2, 1.3)
    direction = Vector((0.0, 0.0, 0.9)) - cam.location
    cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = 3.0
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (np.radians(40), np.radians(10), np.radians(30))
    scene.collection.objects.link(sun)

    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "MATERIAL"
    scene.display.shading.show_shadows = False
    scene.render.resolution_x, scene.render.resolution_y = 480, 270
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False


def export_glb(path: Path):
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.export_scene.gltf(
        filepath=str(path),
        export_format="GLB",
        export_animations=True,
        export_animation_mode="ACTIONS",
        export_skins=True,
        export_morph=False,
        export_cameras=False,
        export_lights=False,
        export_materials="NONE",
        export_yup=True,
        export_anim_slide_to_zero=True,  # time 0 is frame 1: a cycle is [0, duration)
    )


def _pixels(path: Path) -> np.ndarray:
    img = bpy.data.images.load(str(path))
    px = np.empty(img.size[0] * img.size[1] * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    out = px.reshape(img.size[1], img.size[0], 4)
    bpy.data.images.remove(img)
    return out


def _save_pixels(px: np.ndarray, path: Path) -> None:
    img = bpy.data.images.new(path.stem, px.shape[1], px.shape[0], alpha=True)
    img.pixels.foreach_set(px.ravel())
    img.filepath_raw = str(path)
    img.file_format = "PNG"
    img.save()
    bpy.data.images.remove(img)


class _Views:
    """Temporary orthographic cameras looking at the character, removed on exit."""

    PLACES = {
        "left": (6.0, 0.0, 0.9),  # the character's left side (it walks towards -Y)
        "front": (0.0, -6.0, 0.9),
        "three_quarter": (3.2, -5.0, 1.6),
    }

    def __enter__(self):
        self.cams = {}
        for name, place in self.PLACES.items():
            data = bpy.data.cameras.new(f"check_{name}")
            data.type = "ORTHO"
            data.ortho_scale = 2.0
            cam = bpy.data.objects.new(f"check_{name}", data)
            bpy.context.scene.collection.objects.link(cam)
            cam.location = place
            cam.rotation_euler = (Vector((0.0, 0.0, 0.9)) - cam.location).to_track_quat("-Z", "Y").to_euler()
            self.cams[name] = cam
        return self.cams

    def __exit__(self, *exc):
        for cam in self.cams.values():
            data = cam.data
            bpy.data.objects.remove(cam)
            bpy.data.cameras.remove(data)


def _strip(rig, action, cam, count: int, size: tuple[int, int], tmp: Path) -> np.ndarray:
    """`count` frames spread over one cycle of `action`, side by side (RGBA, rows bottom-up)."""
    scene = bpy.context.scene
    rig.animation_data.action = action
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = size
    start, end = (int(x) for x in action.frame_range)
    row = []
    for k in range(count):
        scene.frame_set(start + k * (end - start) // count)
        scene.render.filepath = str(tmp)
        bpy.ops.render.render(write_still=True)
        row.append(_pixels(tmp))
    tmp.unlink()
    return np.concatenate(row, axis=1)


def render(rig, actions: dict[str, bpy.types.Action], out: Path, docs_img: Path | None = None):
    """Contact sheets into `out`: per action 8 frames of one cycle seen from the character's
    left, front and three-quarter front (rows top to bottom, cells 200 x 300). With `docs_img`,
    also the small previews of the docs: 5 frames of each action in three-quarter view."""
    scene = bpy.context.scene
    out.mkdir(parents=True, exist_ok=True)
    saved = rig.animation_data.action, scene.camera, scene.render.resolution_x, scene.render.resolution_y
    tmp = out / "cell.png"
    try:
        with _Views() as cams:
            for name, action in actions.items():
                rows = [_strip(rig, action, cams[v], 8, (200, 300), tmp) for v in ("left", "front", "three_quarter")]
                # Image rows run bottom-up: the first row goes last to end on top.
                _save_pixels(np.concatenate(rows[::-1], axis=0), out / f"{name}_sheet.png")
                if docs_img is not None:
                    docs_img.mkdir(parents=True, exist_ok=True)
                    strip = _strip(rig, action, cams["three_quarter"], 5, (120, 180), tmp)
                    _save_pixels(strip, docs_img / f"character-{name}.png")
    finally:
        rig.animation_data.action, scene.camera = saved[0], saved[1]
        scene.render.resolution_x, scene.render.resolution_y = saved[2], saved[3]
        scene.frame_set(1)


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=SAMPLES, help="folder for character.blend and .glb")
    ap.add_argument("--render", type=Path, help="render contact sheets of each action into this folder")
    ap.add_argument("--docs-img", type=Path, help="with --render: also write the docs' preview strips here")
    args = ap.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.preferences.filepaths.save_version = 0  # no character.blend1 backup beside it
    verts, tris = body_joints.read_obj(SOURCE)
    verts = body_joints.y_up_to_z_up(verts)
    joints = body_joints.find_joints(verts, tris)
    body = build_body(verts, tris)
    rig = build_armature(joints)
    unweighted = skin(body, rig)
    print(f"character: {len(verts)} vertices, {len(tris)} triangles; {unweighted} without bone weights")
    if unweighted:
        raise SystemExit("automatic weights left vertices unweighted: the rig does not fit the body")
    bones = motions.skeleton()
    actions = {name: key_action(rig, name, motions.frames(bones, joints, g)) for name, g in ACTIONS}
    stage(rig, actions)
    args.out.mkdir(parents=True, exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(args.out / "character.blend"), compress=True)
    export_glb(args.out / "character.glb")
    print(f"character: wrote {args.out / 'character.blend'} and {args.out / 'character.glb'}")
    if args.render:
        render(rig, actions, args.render, args.docs_img)
        print(f"character: renders in {args.render}")


if __name__ == "__main__":
    main(sys.argv[1:] if "--" not in sys.argv else sys.argv[sys.argv.index("--") + 1 :])
