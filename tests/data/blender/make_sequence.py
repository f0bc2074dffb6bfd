"""Render a tiny glinty multi-layer EXR image sequence with Blender Cycles.

Test data for glintlab's `measure` command: flicker measured along the motion
vectors of a renderer that glintlab did not write. Run it through make.sh, or:

    blender -b --factory-startup -noaudio --python-exit-code 1 \
        --python make_sequence.py -- --out DIR

Written for Blender 3.4 (Debian 12 package `blender`). The scene is built here
from nothing, no .blend file is read:

  * a finite ground plane whose material is a field of tiny mirror-like facets:
    a 2D Voronoi texture gives each cell (4 cm, about one to two cells per
    pixel) its own random normal, tilted ~16 degrees on average, and a
    Principled BSDF with a low roughness (0.1) reflects a small sun lamp off
    the few facets that happen to face it, so the image has sparse, sub-pixel,
    very bright highlights (glints; the brightest pixel is 600-1500x the
    frame's mean at 1 spp, 120-270x in the reference);
    the cells are not smaller, nor the lobe narrower, on purpose: a glint
    must cover a good part of its pixel, so that a sample finds it with a
    probability not far below 1 and the error falls like 1/sqrt(spp). With
    much smaller glints (the first version: 60 cells/m, roughness 0.06) a
    glint is a rare firefly at 1, 4 and 16 spp alike (value A/spp, found
    spp * p times) and the mean absolute error, flicker included, barely
    changes with the sample count;
  * a sphere floating in front of the ground, so there is a silhouette and,
    because it is nearer than the ground behind it, disocclusion as the camera
    moves; the far edge of the plane is in view too, with the empty world
    (background) beyond it;
  * a camera that slides sideways, speeding up, and sinks slowly (a key on
    every frame, linear extrapolation so that frames 1 and N have motion
    vectors too); see camera_path for the numbers.

The same animation is rendered at several sample counts into DIR/spp1,
DIR/spp4, DIR/spp16 and DIR/ref (the converged reference), each file
DIR/<set>/frame_0001.exr ... (OpenEXR MultiLayer, 32-bit float, ZIP), with the
view layer passes Combined, Vector (motion vectors) and Z (Depth). Motion blur
is off (Cycles writes the Vector pass only then), denoising is off and the
seed is animated, so the noise changes from frame to frame like a real-time
renderer's would.

What the files hold, as measured on them (not taken from documentation):

  * channels: ViewLayer.Combined.{R,G,B,A}, ViewLayer.Depth.Z,
    ViewLayer.Vector.{X,Y,Z,W}; A is 1 everywhere; EXR row 0 is the top row;
  * Vector, in pixels, y pointing UP (so a row offset is -Y or -W):
      (X, Y) = position of the surface point in frame t-1 minus its position
               in frame t (points to the previous frame);
      (Z, W) = position in frame t minus position in frame t+1 (the NEGATED
               offset to the next frame; same orientation as X, Y);
    averaged over the samples of the pixel that hit a surface (mixed values
    at silhouettes; varies with the sample count), 0 where none did;
  * Depth: planar camera depth (distance along the view axis, not along the
    ray) of the pixel-centre ray: identical in every set, not filtered, no
    mixed values at silhouettes; 1e10 where that ray hits nothing.
"""

import argparse
import glob
import math
import os
import sys
import time

import bpy


def parse_args():
    # Blender passes everything after "--" to the script untouched.
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)),
                   help="output folder; <set>/frame_####.exr are written under it")
    p.add_argument("--width", type=int, default=80)
    p.add_argument("--height", type=int, default=45)
    p.add_argument("--frames", type=int, default=8)
    p.add_argument("--spp", type=int, nargs="+", default=[1, 4, 16],
                   help="sample counts of the noisy sets (folders sppN)")
    p.add_argument("--ref-spp", type=int, default=4096,
                   help="sample count of the reference set (folder ref)")
    p.add_argument("--seed-offset", type=int, default=0,
                   help="added to every set's seed (default seed: its sample "
                        "count), e.g. a second reference to check convergence: "
                        "--only ref --seed-offset 1")
    p.add_argument("--only", nargs="+", default=None,
                   help="render only these sets, e.g. --only spp1 ref")
    return p.parse_args(argv)


# --------------------------------------------------------------------------
# Scene construction
# --------------------------------------------------------------------------

def clear_scene():
    """Start from an empty scene (factory startup has a cube, lamp, camera)."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights,
                 bpy.data.cameras, bpy.data.worlds):
        for block in list(coll):
            coll.remove(block)


def link(ob):
    bpy.context.scene.collection.objects.link(ob)
    return ob


def make_glint_material():
    """Principled BSDF on a carpet of tiny randomly oriented facets.

    normal = normalize((0, 0, 1) + TILT * (2 * cell_color - 1))

    where cell_color is the Voronoi cell's random colour (uniform in [0,1)^3),
    so every cell is a flat facet with its own normal. With a low roughness
    only the facets whose normal is close to the half vector between the
    camera and the sun light up: sparse, sub-pixel glints.
    """
    mat = bpy.data.materials.new("Glints")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    n = nt.nodes.new

    out = n("ShaderNodeOutputMaterial")
    bsdf = n("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.06, 0.06, 0.07, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Specular"].default_value = 1.0  # F0 = 0.08
    bsdf.inputs["Roughness"].default_value = 0.10
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])

    coords = n("ShaderNodeTexCoord")
    vor = n("ShaderNodeTexVoronoi")
    vor.voronoi_dimensions = "2D"       # cells on the plane itself
    vor.feature = "F1"
    vor.inputs["Scale"].default_value = 25.0   # 25 cells per metre (see the top)
    vor.inputs["Randomness"].default_value = 1.0
    nt.links.new(coords.outputs["Object"], vor.inputs["Vector"])

    # cell colour in [0,1)^3 -> tilt vector in [-TILT, TILT)^3
    tilt = 0.35
    centred = n("ShaderNodeVectorMath")
    centred.operation = "MULTIPLY_ADD"
    centred.inputs[1].default_value = (2 * tilt, 2 * tilt, 2 * tilt)
    centred.inputs[2].default_value = (-tilt, -tilt, 1.0 - tilt)  # + up
    nt.links.new(vor.outputs["Color"], centred.inputs[0])
    norm = n("ShaderNodeVectorMath")
    norm.operation = "NORMALIZE"
    nt.links.new(centred.outputs["Vector"], norm.inputs[0])
    # The plane is not rotated, so object space == world space here.
    nt.links.new(norm.outputs["Vector"], bsdf.inputs["Normal"])
    return mat


def make_plain_material(name, color, roughness):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    return mat


def camera_path(f, frames):
    """Camera position (x, y, z) in metres at frame f (1..frames).

    x: the step from frame k to k+1 grows linearly from 0.025 m to 0.065 m
       (constant acceleration), centred on x = 0;
    z: sinks 0.03 m per frame from 3 m.

    The focal length in pixels is 50/36 * width (111 px at width 80), so the
    ground (planar depth 3.4..7.4 m) moves 0.3 to 1.9 px/frame sideways and
    0.4 to 0.6 px/frame vertically (measured on the Vector pass at 80x45),
    and the floating sphere faster than the ground next to it. The motion to the
    previous frame and to the next one differ in length, and there is a
    vertical component, so a test can tell the two Vector channel pairs
    apart and find the sign of y.
    """
    n = frames - 1
    first, last = 0.025, 0.065
    accel = (last - first) / max(n - 1, 1)
    k = f - 1
    x = first * k + accel * k * (k - 1) / 2.0
    x_end = first * n + accel * n * (n - 1) / 2.0
    return (x - 0.5 * x_end, -5.0, 3.0 - 0.03 * k)


def build_scene(args):
    scene = bpy.context.scene
    clear_scene()

    # World: a dim, uniform grey-blue sky (this is what background pixels show).
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.20, 0.24, 0.30, 1.0)
    bg.inputs["Strength"].default_value = 0.5
    scene.world = world

    # Ground: a 12 m x 6 m plane at z = 0, from y = -4 to y = 2. The camera sees
    # past its far edge (y = 2) in the top 8 rows (at 45 rows). Vertices are given in world
    # units so that object coordinates (used by the Voronoi) are metres.
    mesh = bpy.data.meshes.new("Ground")
    mesh.from_pydata([(-6, -4, 0), (6, -4, 0), (6, 2, 0), (-6, 2, 0)],
                     [], [(0, 1, 2, 3)])
    mesh.materials.append(make_glint_material())
    link(bpy.data.objects.new("Ground", mesh))

    # Sphere: floats 0.75 m above the ground, nearer to the camera (planar
    # depth 3.7-4.1 m) than the ground next to it (~6 m), so it moves ~1.35x
    # faster in the image and uncovers ground on one side.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32,
                                         radius=0.25, location=(0.2, -1.5, 1.0))
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    bpy.ops.object.shade_smooth()
    sphere.data.materials.append(
        make_plain_material("SphereMat", (0.6, 0.15, 0.08), 0.45))

    # Sun: a small disc (1.5 degrees) 30 degrees above the horizon in front of
    # the camera, 8 degrees off to the side, near the mirror direction of the
    # camera rays, so that facets all over the ground catch it with a modest
    # tilt. Its rotation points the light's -Z axis along the light direction.
    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = 4.0                     # W/m^2
    sun_data.angle = math.radians(1.5)
    sun = link(bpy.data.objects.new("Sun", sun_data))
    sun.rotation_euler = (math.radians(-60.0), 0.0, math.radians(-8.0))

    # Camera: 50 mm lens on a 36 mm sensor (horizontal fit), 3 m up, looking
    # 30 degrees down towards +Y. It slides along +X, speeding up, while
    # sinking slowly (see camera_path).
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 50.0
    cam_data.sensor_width = 36.0
    cam_data.sensor_fit = "HORIZONTAL"
    cam = link(bpy.data.objects.new("Camera", cam_data))
    cam.rotation_euler = (math.radians(60.0), 0.0, 0.0)
    scene.camera = cam

    scene.frame_start = 1
    scene.frame_end = args.frames
    for f in range(1, args.frames + 1):
        cam.location = camera_path(f, args.frames)
        cam.keyframe_insert("location", frame=f)
        print("make_sequence: frame %d camera at (%.5f, %.5f, %.5f)"
              % ((f,) + tuple(cam.location)), flush=True)
    for fc in cam.animation_data.action.fcurves:
        # A key on every frame, straight lines between them, and straight
        # lines beyond the first and last keys: Cycles evaluates the camera
        # one frame before and after each frame for the Vector pass, and with
        # the default constant extrapolation frames 1 and N would get no
        # motion towards frame 0 / N+1.
        fc.extrapolation = "LINEAR"
        for kp in fc.keyframe_points:
            kp.interpolation = "LINEAR"
    return scene


def configure_render(scene, args):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = args.width
    r.resolution_y = args.height
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False       # Combined.A == 1 everywhere
    r.use_motion_blur = False        # required: no Vector pass with blur on
    r.use_compositing = False
    r.use_sequencer = False
    r.use_persistent_data = False

    # Reproducible headers: no date, time, host, render time or file path.
    for attr in ("use_stamp_date", "use_stamp_time", "use_stamp_render_time",
                 "use_stamp_memory", "use_stamp_hostname", "use_stamp_filename",
                 "use_stamp_frame_range", "use_stamp_lens", "use_stamp_marker",
                 "use_stamp_sequencer_strip", "use_stamp_note"):
        setattr(r, attr, False)

    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False  # exactly N samples in every pixel
    c.use_denoising = False
    c.use_preview_denoising = False
    c.use_animated_seed = True       # new noise pattern every frame
    c.max_bounces = 4
    c.diffuse_bounces = 2
    c.glossy_bounces = 2
    c.transmission_bounces = 0
    c.transparent_max_bounces = 0
    c.volume_bounces = 0
    c.caustics_reflective = False
    c.caustics_refractive = False
    c.sample_clamp_direct = 0.0      # no clamping: keep glints at full energy
    c.sample_clamp_indirect = 0.0

    # Linear output (EXR is written scene-linear anyway; this keeps any
    # preview identical).
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"

    vl = scene.view_layers[0]
    vl.name = "ViewLayer"
    vl.use_pass_combined = True
    vl.use_pass_z = True             # "Depth" in the EXR
    vl.use_pass_vector = True        # "Vector" in the EXR (X, Y, Z, W)
    vl.use_pass_mist = False
    vl.use_pass_normal = False
    vl.cycles.denoising_store_passes = False

    img = r.image_settings
    img.file_format = "OPEN_EXR_MULTILAYER"
    img.color_depth = "32"
    img.exr_codec = "ZIP"
    img.color_mode = "RGBA"
    r.use_file_extension = True
    r.use_overwrite = True
    r.use_placeholder = False


def render_set(scene, folder, samples, seed):
    os.makedirs(folder, exist_ok=True)
    for old in glob.glob(os.path.join(folder, "frame_*.exr")):
        os.remove(old)               # no stale frames from a longer run
    scene.cycles.samples = samples
    scene.cycles.seed = seed         # distinct per set: no shared noise
    scene.render.filepath = os.path.join(folder, "frame_####")
    t0 = time.time()
    bpy.ops.render.render(animation=True, write_still=False)
    dt = time.time() - t0
    print("make_sequence: %s: %d spp, %d frames, %.1f s"
          % (folder, samples, scene.frame_end - scene.frame_start + 1, dt),
          flush=True)
    return dt


def main():
    args = parse_args()
    scene = build_scene(args)
    configure_render(scene, args)
    sets = [("spp%d" % s, s) for s in args.spp] + [("ref", args.ref_spp)]
    if args.only:
        sets = [s for s in sets if s[0] in args.only]
    total = 0.0
    for name, spp in sets:
        # The seed is the sample count (+ --seed-offset): each set has its own
        # noise, and rendering a subset (--only) gives the same files as a
        # full run.
        total += render_set(scene, os.path.join(os.path.abspath(args.out), name),
                            spp, seed=spp + args.seed_offset)
    print("make_sequence: total %.1f s" % total, flush=True)


main()
