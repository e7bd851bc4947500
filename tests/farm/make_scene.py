"""Inside Blender: writes a three-frame Purl animation for the farm tests and measurements.

    blender -b --factory-startup --addons purl --python tests/farm/make_scene.py -- out.blend \\
        [--size 64x48] [--samples 4] [--yarns 3] [--environment sky.exr]

Wavy yarns (Bezier curve objects) across the view rise between frames 1 and 3 under a sun and a
grey world (or an Environment Texture of the given image, not packed). Frames are written as 32-bit uncompressed multilayer EXR, so the tests compare pixels
exactly; Purl settings: the given samples, seed 5, animated seed on.
"""
import argparse
import math
import sys

import bpy


def add_yarn(scene, name, z, phase):
    curve = bpy.data.curves.new(name, "CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = 0.1
    spline = curve.splines.new("BEZIER")
    xs = [-3.0 + 0.75 * i for i in range(9)]
    spline.bezier_points.add(len(xs) - 1)
    for point, x in zip(spline.bezier_points, xs):
        point.co = (x, 0.15 * math.sin(2.0 * x + phase), z + 0.05 * math.cos(3.0 * x + phase))
        point.handle_left_type = point.handle_right_type = "AUTO"
    ob = bpy.data.objects.new(name, curve)
    scene.collection.objects.link(ob)
    return ob


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("output")
    parser.add_argument("--size", default="64x48")
    parser.add_argument("--samples", type=int, default=4)
    parser.add_argument("--yarns", type=int, default=3)
    parser.add_argument("--environment", help="an image file for the world's Environment Texture")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:])

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "PURL"
    width, height = (int(v) for v in args.size.split("x"))
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.frame_start, scene.frame_end = 1, 3
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.exr_codec, settings.color_depth = "NONE", "32"
    scene.purl.samples = args.samples
    scene.purl.seed = 5
    scene.purl.use_animated_seed = True

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.location, camera.rotation_euler = (0.0, -4.0, 0.0), (math.pi / 2, 0.0, 0.0)
    rig = bpy.data.objects.new("Yarns", None)
    scene.collection.objects.link(rig)
    for i in range(args.yarns):
        z = -0.6 + 1.2 * (i + 0.5) / args.yarns
        add_yarn(scene, "Yarn{}".format(i), z, 0.7 * i).parent = rig
    rig.location.z = -0.2
    rig.keyframe_insert("location", frame=1)
    rig.location.z = 0.2
    rig.keyframe_insert("location", frame=3)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (-0.7, 0.3, 0.0)
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.02, 0.02, 0.02)
    if args.environment:
        scene.world.use_nodes = True
        tree = scene.world.node_tree
        texture = tree.nodes.new("ShaderNodeTexEnvironment")
        texture.image = bpy.data.images.load(args.environment)
        tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    bpy.ops.wm.save_as_mainfile(filepath=args.output)


if __name__ == "__main__":
    main()
