"""Imports WheelPose's exports of seated clips into Blender and checks them against the clips.

Run inside Blender (tests/blender/run.sh does):
    blender -b --factory-startup --python check_imports.py -- DIR [CLIP...]
DIR holds, for each CLIP (default: every seated clip JSON in DIR), CLIP.json (the seated clip)
and CLIP.fbx, CLIP.glb, CLIP.bvh and, when FBX2glTF ran, CLIP.sdk.glb (the FBX as the Autodesk
FBX SDK reads it, sampled every 1/60 s). Each file is imported into an empty scene with the
importer's defaults (BVH: "update scene fps" on, as a user importing a 120 fps BVH needs) and
checked:
  * 23 bones named as the clip's joints;
  * one key per frame (per 1/60 s for the SDK's samples) on every rotation curve;
  * the keys span the clip's duration at the scene's frame rate;
  * the skinned stick figure (fbx, glb) has a vertex within 1 mm of each wrist mid-clip;
  * both wrists' world positions within 1 mm of the clip at every frame and at every 1/60 s that
    falls on a frame; between frames (the other 1/60 s samples, and halfway between frames)
    within 1 mm of the clip's forward kinematics with its rotations slerped between frames, for
    fbx and glb; see VARIANTS for the BVH and the SDK.
Prints one line per file and the measured errors; exits 1 if any check fails.
"""

import builtins
import json
import math
import os
import sys

import bpy
import numpy
from mathutils import Quaternion, Vector

TOLERANCE_M = 1e-3
WRISTS = ("left_wrist", "right_wrist")


def patch_importers():
    # Debian 12's Blender 3.4.1 runs on Python 3.11 and numpy 1.24, which break two of its own
    # importers: the BVH importer opens files with mode 'rU' (ValueError since Python 3.11) and
    # the glTF importer uses np.bool (removed in numpy 1.24). Patch both before importing.
    import io_anim_bvh.import_bvh as import_bvh

    def open_without_u(path, mode="r", *args, **kwargs):
        return builtins.open(path, mode.replace("U", ""), *args, **kwargs)

    import_bvh.open = open_without_u
    if "bool" not in numpy.__dict__:  # (hasattr would warn)
        numpy.bool = bool


class Clip:
    def __init__(self, path):
        with open(path) as f:
            data = json.load(f)
        self.name = data["name"]
        self.fps = data["fps"]
        self.frames = data["frame_count"]
        self.joints = data["skeleton"]["joints"]
        self.parents = data["skeleton"]["parents"]
        self.rest = [Vector(v) for v in data["skeleton"]["rest_offsets"]]
        self.roots = [Vector(v) for v in data["root_positions"]]
        self.rotations = [[Quaternion(q) for q in frame] for frame in data["local_rotations"]]
        self.positions = [[Vector(p) for p in frame] for frame in data["positions"]]
        self.order = []  # parents before children
        done = set()
        while len(self.order) < len(self.joints):
            for j, parent in enumerate(self.parents):
                if j not in done and (parent < 0 or parent in done):
                    self.order.append(j)
                    done.add(j)

    def duration(self):
        return (self.frames - 1) / self.fps

    def pose(self, seconds):
        """Joint positions at `seconds`: root lerped, local rotations slerped between frames."""
        s = min(max(seconds * self.fps, 0.0), self.frames - 1)
        k = min(int(math.floor(s)), self.frames - 1)
        nxt = min(k + 1, self.frames - 1)
        w = s - k
        root = self.roots[k].lerp(self.roots[nxt], w)
        world_rot = [None] * len(self.joints)
        pos = [None] * len(self.joints)
        for j in self.order:
            local = self.rotations[k][j].slerp(self.rotations[nxt][j], w)
            parent = self.parents[j]
            if parent < 0:
                pos[j] = root
                world_rot[j] = local
            else:
                pos[j] = pos[parent] + world_rot[parent] @ self.rest[j]
                world_rot[j] = world_rot[parent] @ local
        return pos


def to_blender(v):
    # The clip is +Y up, facing +Z; every importer turns that into Blender's +Z up, facing -Y.
    return Vector((v.x, -v.z, v.y))


def import_file(path, rotate_mode):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    patch_importers()
    if path.endswith(".fbx"):
        bpy.ops.import_scene.fbx(filepath=path)
    elif path.endswith(".glb"):
        bpy.ops.import_scene.gltf(filepath=path)
    else:
        bpy.ops.import_anim.bvh(filepath=path, update_scene_fps=True, update_scene_duration=True,
                                rotate_mode=rotate_mode)
    armatures = [o for o in bpy.context.scene.objects if o.type == "ARMATURE"]
    if len(armatures) != 1:
        raise RuntimeError(f"{len(armatures)} armatures")
    return armatures[0]


def fastest_turn(clip):
    """Largest angle (radians) any joint turns between two frames."""
    return max((clip.rotations[k - 1][j].rotation_difference(clip.rotations[k][j]).angle
                for k in range(1, clip.frames) for j in range(len(clip.joints))), default=0.0)


def check_file(clip, path, variant):
    """Returns (summary line, list of failures)."""
    failures = []
    arm = import_file(path, variant.rotate_mode)
    scene = bpy.context.scene
    bones = sorted(b.name for b in arm.data.bones)
    if bones != sorted(clip.joints):
        failures.append(f"bones {bones} are not the clip's {len(clip.joints)} joints")
    action = arm.animation_data.action if arm.animation_data else None
    if action is None:
        return f"{path}: no animation", failures + ["no animation"]
    if variant.baked_60:
        # FBX2glTF samples the FBX SDK's evaluation every 1/60 s up to the last whole sample.
        key_count = int(math.floor(clip.duration() * 60 + 1e-9)) + 1
        span = (key_count - 1) / 60.0
    else:
        key_count, span = clip.frames, clip.duration()
    key_frames = [k.co.x for fc in action.fcurves for k in fc.keyframe_points]
    rotation_keys = [len(fc.keyframe_points) for fc in action.fcurves if "rotation" in fc.data_path]
    bad_counts = [n for n in rotation_keys if n != key_count]
    if not rotation_keys or bad_counts:
        failures.append(f"rotation curves with {sorted(set(bad_counts))} keys, expected {key_count}")
    first, last = min(key_frames), max(key_frames)
    scene_rate = scene.render.fps / scene.render.fps_base
    if abs((last - first) - span * scene_rate) > 1e-3:
        failures.append(f"keys span {last - first:.4f} frames, expected {span * scene_rate:.4f} "
                        f"({span:.4f} s at {scene_rate:g} fps)")
    frames_per_second = (last - first) / span if span > 0 else scene_rate

    def wrist_error(times):
        worst = 0.0
        for t in times:
            frame = first + t * frames_per_second
            whole = math.floor(frame)
            scene.frame_set(int(whole), subframe=frame - whole)
            reference = clip.pose(t)
            for name in WRISTS:
                got = arm.matrix_world @ arm.pose.bones[name].head
                worst = max(worst, (got - to_blender(reference[clip.joints.index(name)])).length)
        return worst

    def on_frame(t):
        return abs(t * clip.fps - round(t * clip.fps)) < 1e-9

    at_60 = [i / 60.0 for i in range(int(math.floor(span * 60 + 1e-9)) + 1)]
    samples = {"60 fps on frames": [t for t in at_60 if on_frame(t)],
               "60 fps": at_60}
    if not variant.baked_60:
        samples["frames"] = [k / clip.fps for k in range(clip.frames)]
        samples["halfway"] = [(k + 0.5) / clip.fps for k in range(clip.frames - 1)]
    errors = {rate: wrist_error(times) for rate, times in samples.items()}
    tolerance = {"60 fps on frames": TOLERANCE_M, "frames": TOLERANCE_M}
    if variant.between_tolerance is not None:
        between = variant.between_tolerance(clip)
        tolerance.update({"60 fps": between, "halfway": between})
    for rate, error in errors.items():
        if rate in tolerance and error > tolerance[rate]:
            failures.append(f"wrist {error * 1000:.3f} mm off at {rate} "
                            f"(tolerance {tolerance[rate] * 1000:g} mm)")
    # The skinned stick figure follows the bones: its mesh, as Blender deforms it, has a vertex on
    # each wrist (the tip of the forearm's glyph) at the middle frame.
    meshes = [o for o in scene.objects if o.type == "MESH"]
    skin_error = None
    if meshes:
        t = (clip.frames // 2) / clip.fps
        frame = first + t * frames_per_second
        scene.frame_set(int(math.floor(frame)), subframe=frame - math.floor(frame))
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = meshes[0].evaluated_get(depsgraph)
        vertices = [evaluated.matrix_world @ v.co for v in evaluated.to_mesh().vertices]
        reference = clip.pose(t)
        skin_error = max(min((v - to_blender(reference[clip.joints.index(name)])).length
                             for v in vertices) for name in WRISTS)
        evaluated.to_mesh_clear()
        if skin_error > TOLERANCE_M:
            failures.append(f"skinned mesh {skin_error * 1000:.3f} mm off the wrists")
    elif variant.skinned:
        failures.append("no mesh")
    summary = (f"{os.path.basename(path)}: "
               f"{len(bones)} bones, {max(rotation_keys or [0])} keys, "
               f"frames {first:g}-{last:g} at {scene_rate:g} fps; wrist error max "
               + ", ".join(f"{errors[rate] * 1000:.4f} mm ({rate}"
                           + ("" if rate in tolerance else ", reported only") + ")"
                           for rate in errors))
    if skin_error is not None:
        summary += f"; skinned mesh at the wrists {skin_error * 1000:.4f} mm"
    return summary, failures


class Variant:
    def __init__(self, extension, rotate_mode=None, baked_60=False, between_tolerance=None,
                 skinned=True):
        self.extension = extension
        self.skinned = skinned
        self.rotate_mode = rotate_mode
        self.baked_60 = baked_60
        self.between_tolerance = between_tolerance


def sdk_between_tolerance(clip):
    # The FBX SDK interpolates the Euler curves linearly, which parts from the rotation's path by
    # about the square of the turn between frames (export_fbx_test.cpp measures the same): 1 mm
    # while every joint turns less than 12° per frame, 2.5 mm beyond (tennis_serve: 15°).
    return TOLERANCE_M if math.degrees(fastest_turn(clip)) < 12 else 2.5e-3


VARIANTS = (
    Variant(".fbx", between_tolerance=lambda clip: TOLERANCE_M),
    Variant(".glb", between_tolerance=lambda clip: TOLERANCE_M),
    # Blender keys BVH rotations as Euler angles in each bone's own axes and interpolates those
    # (with rotation mode "Quaternion" it does not keep the quaternions in one hemisphere, so
    # samples between frames can flip); a BVH defines no pose between frames: reported only.
    Variant(".bvh", rotate_mode="NATIVE", skinned=False),
    # The FBX as the Autodesk FBX SDK reads it (FBX2glTF, run by run.sh when installed).
    Variant(".sdk.glb", baked_60=True, between_tolerance=sdk_between_tolerance),
)


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    directory, names = args[0], args[1:]
    if not names:
        for file in sorted(os.listdir(directory)):
            if file.endswith(".json"):
                with open(os.path.join(directory, file)) as f:
                    if json.load(f).get("format") == "wheelpose.seated_clip":
                        names.append(file[:-len(".json")])
    passed = failed = 0
    for name in names:
        clip = Clip(os.path.join(directory, name + ".json"))
        # The reference reproduces the clip's own positions at its frames.
        drift = max((clip.pose(k / clip.fps)[j] - clip.positions[k][j]).length
                    for k in range(clip.frames) for j in range(len(clip.joints)))
        if drift > 1e-5:
            print(f"FAIL {name}: reference forward kinematics is {drift * 1000:.4f} mm off the clip")
            failed += 1
            continue
        for variant in VARIANTS:
            path = os.path.join(directory, name + variant.extension)
            if variant.extension == ".sdk.glb" and not os.path.exists(path):
                continue
            try:
                summary, failures = check_file(clip, path, variant)
            except Exception as error:  # an importer that throws fails this file, not the run
                summary, failures = f"{os.path.basename(path)}: import failed", [repr(error)]
            print(("ok   " if not failures else "FAIL ") + summary)
            for failure in failures:
                print(f"       {failure}")
            passed += not failures
            failed += bool(failures)
    print(f"{passed} passed, {failed} failed")
    sys.stdout.flush()
    os._exit(1 if failed or passed == 0 else 0)


if __name__ == "__main__":
    main()
