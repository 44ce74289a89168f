"""Imports a rigged person (wheelpose body export --rigged) into Blender and checks it.

Run inside Blender (tests/blender/run.sh does):
    blender -b --factory-startup --python check_rigged_person.py -- RIGGED CLIP.json \
        STATIC_A.glb FRAME_A STATIC_B.glb FRAME_B [--baked60]
RIGGED is the glb or the binary FBX; with --baked60 it is FBX2glTF's glb of the FBX (the FBX as
the Autodesk FBX SDK reads it, sampled every 1/60 s), whose keys are those samples and whose
joints are only the bones that move a vertex: all but the rig's root bone "Root".
STATIC_A/B are the same person's static exports at clip frames FRAME_A and FRAME_B
(wheelpose body export --clip CLIP.json --frame F): their body meshes are the vertices our own
skinning (build_person) gives at those frames, in the rigged body mesh's vertex order. Checks:
  * one armature with the rig's 53 bones (52 with --baked60);
  * one key per clip frame on every rotation curve (per 1/60 s with --baked60), keys spanning
    the clip's duration (up to its last whole 1/60 s);
  * the skinned body as Blender deforms it (evaluated depsgraph) moves with the bones: the
    vertex nearest the right wrist at FRAME_A is within 1 mm of our skinning there, and the same
    vertex is within 1 mm of our skinning at FRAME_B, having moved with the arm.
Prints one line with the measured figures; exits 1 if a check fails.
"""

import json
import math
import os
import struct
import sys

import bpy
import numpy
from mathutils import Vector

TOLERANCE_M = 1e-3
BONES = 53


def patch_gltf_importer():
    # Debian 12's Blender 3.4.1 runs on numpy 1.24, whose removed np.bool its glTF importer uses.
    if "bool" not in numpy.__dict__:  # (hasattr would warn)
        numpy.bool = bool


def glb_document(path):
    """(JSON chunk, BIN chunk) of a .glb."""
    with open(path, "rb") as f:
        data = f.read()
    json_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + json_length])
    bin_start = 20 + json_length + 8
    return document, data[bin_start:]


def body_positions(path):
    """POSITION of the mesh named "body", in file order."""
    document, binary = glb_document(path)
    mesh = next(m for m in document["meshes"] if m["name"] == "body")
    accessor = document["accessors"][mesh["primitives"][0]["attributes"]["POSITION"]]
    view = document["bufferViews"][accessor["bufferView"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    values = struct.unpack_from(f"<{3 * accessor['count']}f", binary, start)
    return [Vector(values[3 * i:3 * i + 3]) for i in range(accessor["count"])]


def to_blender(v):
    # Our glb and FBX are +Y up, facing +Z; Blender's importers turn that into +Z up, facing -Y.
    return Vector((v.x, -v.z, v.y))


def deformed_body(scene, frame):
    whole = math.floor(frame)
    scene.frame_set(int(whole), subframe=frame - whole)
    body = next(o for o in scene.objects if o.type == "MESH" and o.data.name == "body")
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = body.evaluated_get(depsgraph)
    vertices = [evaluated.matrix_world @ v.co for v in evaluated.to_mesh().vertices]
    evaluated.to_mesh_clear()
    return vertices


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    baked_60 = "--baked60" in args
    args = [a for a in args if a != "--baked60"]
    rigged, clip_path = args[0], args[1]
    statics = [(args[2], int(args[3])), (args[4], int(args[5]))]
    with open(clip_path) as f:
        clip = json.load(f)
    frames, fps = clip["frame_count"], clip["fps"]
    span = (frames - 1) / fps
    key_count = int(math.floor(span * 60 + 1e-9)) + 1 if baked_60 else frames
    if baked_60:
        span = (key_count - 1) / 60.0
    failures = []

    bpy.ops.wm.read_factory_settings(use_empty=True)
    patch_gltf_importer()
    if rigged.endswith(".fbx"):
        bpy.ops.import_scene.fbx(filepath=rigged)
    else:
        bpy.ops.import_scene.gltf(filepath=rigged)
    scene = bpy.context.scene
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    if len(armatures) != 1:
        print(f"FAIL {os.path.basename(rigged)}: {len(armatures)} armatures")
        sys.stdout.flush()
        os._exit(1)
    arm = armatures[0]
    bones = len(arm.data.bones)
    expected_bones = BONES - 1 if baked_60 else BONES
    if bones != expected_bones:
        failures.append(f"{bones} bones, expected {expected_bones}")
    action = arm.animation_data.action if arm.animation_data else None
    if action is None:
        failures.append("no animation")
        keys, first, last = [0], 0, 0
    else:
        keys = [len(fc.keyframe_points) for fc in action.fcurves if "rotation" in fc.data_path]
        if not keys or set(keys) != {key_count}:
            failures.append(f"rotation curves with {sorted(set(keys))} keys, expected {key_count}")
        key_frames = [k.co.x for fc in action.fcurves for k in fc.keyframe_points]
        first, last = min(key_frames), max(key_frames)
    scene_rate = scene.render.fps / scene.render.fps_base
    if abs((last - first) - span * scene_rate) > 1e-3:
        failures.append(f"keys span {last - first:.4f} frames, expected {span * scene_rate:.4f}")

    def scene_frame(clip_frame):
        return first + clip_frame / fps * scene_rate

    # Our skinning at the two frames (static exports), and the vertex nearest the right wrist.
    ours = [body_positions(path) for path, _ in statics]
    with open(os.path.splitext(statics[0][0])[0] + ".json") as f:
        wrist = Vector(json.load(f)["coco_keypoints"]["right_wrist"])
    index = min(range(len(ours[0])), key=lambda i: (ours[0][i] - wrist).length)
    errors, moved = [], (ours[1][index] - ours[0][index]).length
    blender_vertex = None
    for (path, clip_frame), positions in zip(statics, ours):
        deformed = deformed_body(scene, scene_frame(clip_frame))
        target = to_blender(positions[index])
        if blender_vertex is None:  # Blender may reorder vertices: find ours at the first frame
            blender_vertex = min(range(len(deformed)), key=lambda i: (deformed[i] - target).length)
        errors.append((deformed[blender_vertex] - target).length)
    for (path, clip_frame), error in zip(statics, errors):
        if error > TOLERANCE_M:
            failures.append(f"wrist vertex {error * 1000:.3f} mm off our skinning at frame "
                            f"{clip_frame}")
    if moved < 0.01:
        failures.append(f"the wrist vertex moves only {moved * 1000:.1f} mm between the frames")
    print(("ok   " if not failures else "FAIL ")
          + f"{os.path.basename(rigged)}: {bones} bones, {max(keys)} keys, frames "
          f"{first:g}-{last:g} at {scene_rate:g} fps; right-wrist vertex {index} moves "
          f"{moved * 1000:.1f} mm, off our skinning by "
          + ", ".join(f"{e * 1000:.4f} mm (frame {f})" for (_, f), e in zip(statics, errors)))
    for failure in failures:
        print(f"       {failure}")
    sys.stdout.flush()
    os._exit(1 if failures else 0)


if __name__ == "__main__":
    main()
