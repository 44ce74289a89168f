"""Imports WheelPose's exports of seated clips into Blender and checks them against the clips.

Run inside Blender (tests/blender/run.sh does):
    blender -b --factory-startup --python check_imports.py -- DIR [CLIP...]
DIR holds, for each CLIP (default: every seated clip JSON in DIR), CLIP.json (the seated clip)
and CLIP.fbx, CLIP.glb and CLIP.bvh. Each file is imported into an empty scene with the
importer's defaults (BVH: "update scene fps" on, as a user importing a 120 fps BVH needs) and
checked:
  * 23 bones named as the clip's joints;
  * one key per frame on every rotation curve;
  * the keys span the clip's duration at the scene's frame rate;
  * both wrists' world positions within 1 mm of the clip at every frame, at every 1/60 s and
    halfway between frames. The reference is the clip's forward kinematics with its rotations
    slerped between frames (at frames: the clip's own positions, to 1 µm).
For the BVH, Blender keys Euler angles in each bone's own axes and interpolates them linearly
(and with rotation mode "Quaternion" it does not keep the quaternions in one hemisphere, so
samples between frames can flip); a BVH defines no pose between frames, so there only the
samples that fall on frames are checked and the rest is reported.
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
    if not hasattr(numpy, "bool"):
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


def check_file(clip, path, rotate_mode, between_frames_checked):
    """Returns (summary line, list of failures)."""
    failures = []
    arm = import_file(path, rotate_mode)
    scene = bpy.context.scene
    bones = sorted(b.name for b in arm.data.bones)
    if bones != sorted(clip.joints):
        failures.append(f"bones {bones} are not the clip's {len(clip.joints)} joints")
    action = arm.animation_data.action if arm.animation_data else None
    if action is None:
        return f"{path}: no animation", failures + ["no animation"]
    key_frames = [k.co.x for fc in action.fcurves for k in fc.keyframe_points]
    rotation_keys = [len(fc.keyframe_points) for fc in action.fcurves if "rotation" in fc.data_path]
    bad_counts = [n for n in rotation_keys if n != clip.frames]
    if not rotation_keys or bad_counts:
        failures.append(f"rotation curves with {sorted(set(bad_counts))} keys, expected {clip.frames}")
    first, last = min(key_frames), max(key_frames)
    scene_rate = scene.render.fps / scene.render.fps_base
    expected_span = clip.duration() * scene_rate
    if abs((last - first) - expected_span) > 1e-3:
        failures.append(f"keys span {last - first:.4f} frames, expected {expected_span:.4f} "
                        f"({clip.duration():.4f} s at {scene_rate:g} fps)")
    frames_per_second = (last - first) / clip.duration() if clip.frames > 1 else scene_rate

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

    on_keys = [k / clip.fps for k in range(clip.frames)]
    at_60 = [i / 60.0 for i in range(int(math.floor(clip.duration() * 60 + 1e-9)) + 1)]
    at_60_on_keys = [t for t in at_60 if abs(t * clip.fps - round(t * clip.fps)) < 1e-9]
    halfway = [(k + 0.5) / clip.fps for k in range(clip.frames - 1)]
    errors = {"frames": wrist_error(on_keys), "60 fps": wrist_error(at_60),
              "60 fps on frames": wrist_error(at_60_on_keys), "halfway": wrist_error(halfway)}
    checked = ["frames", "60 fps on frames"]
    if between_frames_checked:
        checked += ["60 fps", "halfway"]
    for rate in checked:
        if errors[rate] > TOLERANCE_M:
            failures.append(f"wrist {errors[rate] * 1000:.3f} mm off at {rate}")
    summary = (f"{os.path.basename(path)}: "
               f"{len(bones)} bones, {max(rotation_keys or [0])} keys, "
               f"frames {first:g}-{last:g} at {scene_rate:g} fps; wrist error max "
               + ", ".join(f"{errors[rate] * 1000:.4f} mm ({rate}"
                           + ("" if rate in checked else ", reported only") + ")"
                           for rate in errors))
    return summary, failures


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    directory, names = args[0], args[1:]
    if not names:
        for file in sorted(os.listdir(directory)):
            if file.endswith(".json"):
                with open(os.path.join(directory, file)) as f:
                    if json.load(f).get("format") == "wheelpose.seated_clip":
                        names.append(file[:-len(".json")])
    # (extension, BVH rotation mode, whether poses between frames are checked)
    imports = ((".fbx", None, True), (".glb", None, True), (".bvh", "NATIVE", False))
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
        for extension, rotate_mode, between in imports:
            path = os.path.join(directory, name + extension)
            try:
                summary, failures = check_file(clip, path, rotate_mode, between)
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


main()
