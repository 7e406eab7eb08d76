"""Blender (Debian's `blender`, Cycles on the CPU) as a third-party consumer of `nephele export-vdb`.

Run inside Blender:
  blender -b --factory-startup --python blender_vdb.py -- MODE VDB OUT [options]
MODE
  absorption  top-down orthographic camera over the grid's footprint, one pixel per model column,
              a black Volume Absorption shader driven by the VDB's `density` grid, transparent
              film. Cycles' alpha is then 1 − exp(−τ) with τ the column's optical depth, the
              closed form blender_check.py compares against. Writes OUT.npy (alpha, row 0 =
              south) and OUT.png.
  beauty      Principled Volume (density from the grid, white scattering, g = 0.85 forward
              scattering as cloud droplets) lit by a sun, perspective camera; writes OUT.png.
Options: --samples N; --size WxH (beauty); --camera X,Y,Z,TX,TY,TZ,VFOV_DEG in the VDB's world
frame (beauty); --sun AZIMUTH_DEG,ELEVATION_DEG (beauty); --z-scale S (heights × S about the
ground, as nephele's height_exaggeration, beauty).
The volume object keeps the VDB's transform: 1 Blender unit = 1 m, so density [1/m] is extinction.
"""
import math
import sys

import bpy
import numpy as np
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:]
mode, vdb_path, out = argv[0], argv[1], argv[2]
opts = dict(zip(argv[3::2], argv[4::2]))
samples = int(opts.get("--samples", "16"))

# ---- scene -------------------------------------------------------------------------------------
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.seed = 1
scene.cycles.pixel_filter_type = "BOX"  # each pixel averages exactly its own footprint
scene.cycles.filter_width = 1.0
scene.render.film_transparent = True
scene.render.use_persistent_data = False

volume = bpy.data.volumes.new("storm")
volume.filepath = vdb_path
obj = bpy.data.objects.new("storm", volume)
scene.collection.objects.link(obj)
volume.grids.load()
# Blender skips voxels below render.clipping (default 0.001) when it bounds the volume: cloud
# extinction is 1e-5..1e-2 per metre, so nothing would be left. Keep every active voxel.
volume.render.clipping = 0.0
names = [g.name for g in volume.grids]
if "density" not in names:
    sys.exit(f"blender_vdb: {vdb_path} has no 'density' grid (grids: {names})")

# The grid's index -> object transform as Blender read it (scale-translate: nephele's frame).
# (Not pyopenvdb: importing it into Blender's process breaks Blender's own OpenVDB reads.)
m = volume.grids["density"].matrix_object
dx, dy, dz = m[0][0], m[1][1], m[2][2]
x0, y0, z0 = m[0][3], m[1][3], m[2][3]
# Blender 3.4 renders voxel (i, j, k) centred at index (i, j, k) + ½ — half a voxel off the
# OpenVDB convention (centre at the integer index, which transform and Houdini follow; measured
# here: a centroid shift of +0.50 px in x and y without this). Move the object back by half a voxel.
obj.location = (-0.5 * dx, -0.5 * dy, -0.5 * dz)
bpy.context.view_layer.update()
z_top = max(corner[2] for corner in obj.bound_box)  # top of the active voxels

material = bpy.data.materials.new("cloud")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
nodes.clear()
output = nodes.new("ShaderNodeOutputMaterial")
attribute = nodes.new("ShaderNodeAttribute")
attribute.attribute_name = "density"
if mode == "absorption":
    # Cycles: σ_a = density·(1 − colour); a black colour would be a zero-weight closure, which
    # Cycles drops, so colour ½ and density × 2 give σ_a = β exactly.
    shader = nodes.new("ShaderNodeVolumeAbsorption")
    shader.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    twice = nodes.new("ShaderNodeMath")
    twice.operation = "MULTIPLY"
    twice.inputs[1].default_value = 2.0
    links.new(attribute.outputs["Fac"], twice.inputs[0])
    links.new(twice.outputs[0], shader.inputs["Density"])
else:
    shader = nodes.new("ShaderNodeVolumePrincipled")
    shader.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    shader.inputs["Anisotropy"].default_value = 0.85
    shader.inputs["Density Attribute"].default_value = ""
    links.new(attribute.outputs["Fac"], shader.inputs["Density"])
links.new(shader.outputs[0], output.inputs["Volume"])
obj.data.materials.append(material)

camera_data = bpy.data.cameras.new("camera")
camera = bpy.data.objects.new("camera", camera_data)
scene.collection.objects.link(camera)
scene.camera = camera

if mode == "absorption":
    # The whole grid index range [0, n) → pixels: pixel (i, j) centred over column (i, j).
    nx, ny = int(opts["--columns"].split("x")[0]), int(opts["--columns"].split("x")[1])
    scene.render.resolution_x, scene.render.resolution_y = nx, ny
    scene.render.resolution_percentage = 100
    camera_data.type = "ORTHO"
    camera_data.sensor_fit = "HORIZONTAL" if nx * dx >= ny * dy else "VERTICAL"
    camera_data.ortho_scale = max(nx * dx, ny * dy)
    if abs(dx - dy) > 1e-6 * dx:
        sys.exit(f"blender_vdb: absorption mode needs square columns, {vdb_path} has {dx} x {dy} m")
    top = z_top + 2.0 * dz
    camera.location = (x0 + (nx - 1) * 0.5 * dx, y0 + (ny - 1) * 0.5 * dy, top + 1000.0)
    camera.rotation_euler = (0.0, 0.0, 0.0)  # looking down −z, image up = +y (north)
    camera_data.clip_start = 1.0
    # Far clip well below sea level (a clip_end that ended 2 km below the volume's bottom cut
    # volumes that start at layer 0 in Cycles 3.4: measured alpha 0 instead of 0.70).
    camera_data.clip_end = top + 1.0e5
    scene.cycles.volume_max_steps = 4096
    # Ray-marching step: half a layer, in metres. ("Automatic" follows the voxel size, which for
    # 15 km × 15 km × 250 m voxels marched a column in a few steps: errors up to 0.08 in alpha.)
    volume.render.space = "WORLD"
    volume.render.step_size = 0.5 * dz
else:
    w, h = (int(v) for v in opts.get("--size", "480x270").split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    cx, cy, cz, tx, ty, tz, vfov = (float(v) for v in opts["--camera"].split(","))
    camera.location = (cx, cy, cz)
    direction = Vector((tx - cx, ty - cy, tz - cz))
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    camera_data.sensor_fit = "VERTICAL"
    camera_data.angle_y = math.radians(vfov)
    camera_data.clip_start = 10.0
    camera_data.clip_end = 1e7
    z_scale = float(opts.get("--z-scale", "1"))
    obj.scale = (1.0, 1.0, z_scale)  # heights × S about z = 0 (mean sea level)
    obj.location.z *= z_scale
    az, el = (float(v) for v in opts.get("--sun", "200,35").split(","))
    sun_data = bpy.data.lights.new("sun", "SUN")
    sun_data.energy = 5.0
    sun = bpy.data.objects.new("sun", sun_data)
    to_sun = Vector((math.sin(math.radians(az)) * math.cos(math.radians(el)),
                     math.cos(math.radians(az)) * math.cos(math.radians(el)), math.sin(math.radians(el))))
    sun.rotation_euler = (-to_sun).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("sky")  # (absorption mode has no world: a node world of
    scene.world = world                  # strength 0 made Cycles 3.4 drop the volume's alpha)
    world.use_nodes = True
    # a dark navy sky like nephele's background without basemap, so thin cloud shows as in nephele
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.01, 0.02, 0.05, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.render.film_transparent = False
    scene.cycles.volume_bounces = 8
    scene.view_settings.view_transform = "Filmic"

scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGBA"
scene.render.filepath = out + ".png"
bpy.ops.render.render(write_still=True)

if mode == "absorption":
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    exr = out + ".exr"
    bpy.data.images["Render Result"].save_render(exr)
    image = bpy.data.images.load(exr)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
    np.save(out + ".npy", pixels[:, :, 3])  # Blender's rows start at the bottom: row 0 = south
    print(f"blender_vdb: alpha {pixels.shape[1]}x{pixels.shape[0]} -> {out}.npy")
