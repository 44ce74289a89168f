"""Renders a glb person in Blender's own renderer (Cycles on the CPU), headless: the picture of a
rigged person imported into Blender, for the README. Not a test.

    blender -b --factory-startup --python render_person.py -- PERSON.glb SCENE_FRAME OUT.png

SCENE_FRAME is Blender's frame (the glTF importer keys at the scene's 24 fps: clip frame 40 of a
30 fps clip is scene frame 32). The camera looks at the person from the front left, as our own
renders do, 512 x 512 pixels, 32 samples (Debian's Blender has no denoiser).
"""

import math
import sys

import bpy
import numpy
from mathutils import Vector


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    path, frame, out = args[0], int(args[1]), args[2]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if "bool" not in numpy.__dict__:  # Debian's Blender 3.4 glTF importer needs np.bool
        numpy.bool = bool
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    scene.frame_set(frame)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    # The person faces glTF's +Z, which is Blender's -Y.
    camera.location = Vector((0.9, -2.0, 1.1))
    camera.rotation_euler = (Vector((0, 0, 0.65)) - camera.location).to_track_quat(
        "-Z", "Y").to_euler()
    camera.data.lens = 45
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3
    sun.rotation_euler = (math.radians(50), 0, math.radians(30))
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("sky")
    scene.world.use_nodes = True
    background = scene.world.node_tree.nodes["Background"]
    background.inputs[0].default_value = (0.8, 0.8, 0.85, 1)
    background.inputs[1].default_value = 0.35
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 32
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 512
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main()
