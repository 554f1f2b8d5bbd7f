"""Lit comparison of a mesh file and its level of detail in Blender: what a
user sees, normal maps included (an instrument for wildlod's evaluation, not
part of the product).

usage (with the Blender environment of ../shared/peers/setup.sh):
  ../shared/peers/bpy tools/blender/lit_compare.py INPUT OUTPUT NAME
      [--dir /tmp/wildlod-lit] [--size 256] [--samples 16] [--views 8]
      [--no-floor] [--frame N]

Both files are imported with Blender's own importers (glTF, OBJ, PLY, STL)
and rendered by Cycles on the CPU (EEVEE needs a GPU context that a headless
machine does not have; it took minutes per frame there), with the materials
as imported: base color, metallic-roughness and normal maps all count. The
views look at the input's bounding sphere (center and half diagonal of its
world-space bounding box, at frame --frame or the scene's current one) from
the 8 corners of a cube around it (azimuth 45° + k·90°, elevation ±35.26°),
framed as ../shared/peers/render.py frames its one view. Each view has its
own key light, a sun 30° up and 30° to the left of the view direction, and
a dim uniform world, the same for both files: every visible side is lit at
an angle, so bumps and normal maps throw shading.

The difference is the mean absolute difference of the displayed 8-bit sRGB
values (RGB channels, 0..1) over the object's pixels: those where either
render covers the object (alpha > 1/2), both composited over the world
gray, so a silhouette that moves counts too. Cycles at low samples is
noisy. Input and output are rendered with the same seed: Cycles draws its
random numbers per pixel, so where both files show the same surface point
through a pixel they get the same paths and the noise cancels, whichever
tool wrote the triangles (unlike sample points drawn per triangle, this
favours no tool). Unless --no-floor, the input is also rendered with
another seed, and its difference to the first render is the noise floor:
what two renders of one file differ by, so a difference well above it is
not noise (`wildlod compare` reports floors for its paired metrics too).

Measured on the 2-core machine (256 px, 16 samples, 24 renders): about a
minute per pair; CesiumMilkTruck at 1% keep-UV 0.179 (floor 0.006),
tea_set_01 at 1% keep-UV 0.131, re-baked 0.054 (floor 0.010).

Writes NAME_vK_in.png, NAME_vK_out.png and NAME_vK_pair.png (input | output
| |difference| × 4) for every view, NAME_sheet.png (all pairs, one row per
view) and NAME.json, and prints the JSON on one line after `RESULT `.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

# The world color the objects are composited over, linear (displayed as
# sRGB ~0.35): dim enough that the key light dominates.
WORLD = 0.1


def args():
    argv = sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser()
    ap.add_argument('input')
    ap.add_argument('output')
    ap.add_argument('name')
    ap.add_argument('--dir', default='/tmp/wildlod-lit')
    ap.add_argument('--size', type=int, default=256)
    ap.add_argument('--samples', type=int, default=16)
    ap.add_argument('--views', type=int, default=8, help='first N of the 8 cube-corner views')
    ap.add_argument('--no-floor', action='store_true')
    ap.add_argument('--frame', type=int)
    return ap.parse_args(argv)


def import_any(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = os.path.splitext(path)[1].lower()
    if ext in ('.gltf', '.glb'):
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == '.obj':
        bpy.ops.wm.obj_import(filepath=path)
    elif ext == '.ply':
        bpy.ops.wm.ply_import(filepath=path)
    elif ext == '.stl':
        bpy.ops.wm.stl_import(filepath=path)
    else:
        raise SystemExit(f'unsupported extension: {path}')
    meshes = [o for o in bpy.context.scene.objects if o.type == 'MESH']
    if not meshes:
        raise SystemExit(f'{path}: no mesh object')
    return meshes


def world_bounds(meshes):
    dg = bpy.context.evaluated_depsgraph_get()
    lo = Vector((math.inf,) * 3)
    hi = Vector((-math.inf,) * 3)
    for o in meshes:
        eo = o.evaluated_get(dg)
        me = eo.to_mesh()
        for v in me.vertices:
            p = eo.matrix_world @ v.co
            lo = Vector(map(min, lo, p))
            hi = Vector(map(max, hi, p))
        eo.to_mesh_clear()
    return lo, hi


def view_directions(n):
    """The 8 corners of a cube: azimuths 45° + k·90°, above and below."""
    dirs = []
    for up in (1, -1):
        for k in range(4):
            a = math.radians(45 + 90 * k)
            dirs.append(Vector((math.cos(a), math.sin(a), up * math.sqrt(0.5))).normalized())
    return dirs[:n]


def key_light_direction(view):
    """Direction the light comes from: the view direction turned 30° up and
    30° to the left (seen from the camera)."""
    up = Vector((0, 0, 1))
    right = view.cross(up)
    if right.length < 1e-6:
        right = Vector((1, 0, 0))
    right.normalize()
    true_up = right.cross(view).normalized()
    t = math.radians(30)
    return (view * math.cos(t) + true_up * math.sin(t) - right * math.sin(t)).normalized()


def setup_render(size, samples, seed):
    sc = bpy.context.scene
    sc.render.engine = 'CYCLES'
    sc.cycles.device = 'CPU'
    sc.cycles.samples = samples
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.seed = seed
    sc.cycles.max_bounces = 2
    sc.cycles.diffuse_bounces = 1
    sc.cycles.glossy_bounces = 1
    sc.cycles.transmission_bounces = 2
    sc.cycles.transparent_max_bounces = 4
    sc.render.film_transparent = True
    sc.render.resolution_x = sc.render.resolution_y = size
    sc.render.resolution_percentage = 100
    sc.render.image_settings.file_format = 'PNG'
    sc.render.image_settings.color_mode = 'RGBA'
    sc.render.image_settings.color_depth = '8'
    sc.view_settings.view_transform = 'Standard'
    sc.view_settings.look = 'None'
    sc.world = bpy.data.worlds.new('w')
    sc.world.use_nodes = True
    bg = sc.world.node_tree.nodes['Background']
    bg.inputs['Color'].default_value = (WORLD, WORLD, WORLD, 1)
    bg.inputs['Strength'].default_value = 1.0


def place(cam_obj, sun_obj, center, radius, view):
    fov = cam_obj.data.angle
    cam_obj.location = center + view * (radius / math.sin(fov / 2) * 1.02)
    cam_obj.rotation_euler = (-view).to_track_quat('-Z', 'Y').to_euler()
    light = key_light_direction(view)
    # A sun shines along its local −Z.
    sun_obj.rotation_euler = (-light).to_track_quat('-Z', 'Y').to_euler()


def render_views(path, center, radius, dirs, opts, seed, prefix):
    meshes = import_any(path)
    if opts.frame is not None:
        bpy.context.scene.frame_set(opts.frame)
    setup_render(opts.size, opts.samples, seed)
    sc = bpy.context.scene
    camd = bpy.data.cameras.new('cam')
    camd.lens = 50
    camd.clip_start, camd.clip_end = radius * 1e-3, radius * 100
    cam = bpy.data.objects.new('cam', camd)
    sc.collection.objects.link(cam)
    sc.camera = cam
    sund = bpy.data.lights.new('key', 'SUN')
    sund.energy = 3.0
    sund.angle = math.radians(2)
    sun = bpy.data.objects.new('key', sund)
    sc.collection.objects.link(sun)
    files = []
    for k, d in enumerate(dirs):
        place(cam, sun, center, radius, d)
        f = os.path.join(opts.dir, f'{prefix}_v{k}.png')
        sc.render.filepath = f
        bpy.ops.render.render(write_still=True)
        files.append(f)
    info = {'mesh_objects': len(meshes),
            'polygons': sum(len(o.data.polygons) for o in meshes),
            'materials': sorted(m.name for m in bpy.data.materials),
            'images': sorted(i.name for i in bpy.data.images if i.size[0] > 0)}
    return files, info


def load_rgba(path):
    """Pixels (rows bottom to top, as Blender stores them), 8-bit values
    as 0..1, RGBA."""
    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float64).reshape(h, w, 4)
    bpy.data.images.remove(img)
    return px


def composite(px):
    """RGB over the world gray as displayed (sRGB-encoded WORLD), and the
    object mask."""
    g = 1.055 * WORLD ** (1 / 2.4) - 0.055
    a = px[..., 3:4]
    return px[..., :3] * a + g * (1 - a), px[..., 3] > 0.5


def difference(a_path, b_path):
    (a, ma), (b, mb) = composite(load_rgba(a_path)), composite(load_rgba(b_path))
    mask = ma | mb
    n = int(mask.sum())
    d = np.abs(a - b).mean(axis=2)
    return (float(d[mask].mean()) if n else 0.0), n, a, b, d


def save_png(arr, path):
    """Saves an (h, w, 3) array (rows bottom to top) as an RGB PNG."""
    h, w = arr.shape[:2]
    rgba = np.concatenate([np.clip(arr, 0, 1), np.ones((h, w, 1))], axis=2)
    img = bpy.data.images.new(os.path.basename(path), w, h)
    img.pixels = rgba.ravel()
    img.filepath_raw, img.file_format = path, 'PNG'
    img.save()
    bpy.data.images.remove(img)


def main():
    o = args()
    os.makedirs(o.dir, exist_ok=True)
    t0 = time.time()
    meshes = import_any(o.input)
    if o.frame is not None:
        bpy.context.scene.frame_set(o.frame)
    lo, hi = world_bounds(meshes)
    center, radius = (lo + hi) / 2, max((hi - lo).length / 2, 1e-9)
    dirs = view_directions(o.views)
    ins, info_in = render_views(o.input, center, radius, dirs, o, 0, f'{o.name}_in')
    outs, info_out = render_views(o.output, center, radius, dirs, o, 0, f'{o.name}_out')
    floors = None
    if not o.no_floor:
        floors, _ = render_views(o.input, center, radius, dirs, o, 1, f'{o.name}_in_seed1')
    views, rows = [], []
    sep = np.zeros((o.size, 4, 3))
    for k, d in enumerate(dirs):
        diff, n, a, b, dmap = difference(ins[k], outs[k])
        v = {'view': k, 'direction': [round(x, 4) for x in d], 'mean_abs_diff': diff,
             'object_pixels': n}
        if floors:
            v['floor'] = difference(ins[k], floors[k])[0]
            os.remove(floors[k])
        views.append(v)
        heat = np.repeat(np.clip(4 * dmap, 0, 1)[..., None], 3, axis=2)
        row = np.concatenate([a, sep, b, sep, heat], axis=1)
        save_png(row, os.path.join(o.dir, f'{o.name}_v{k}_pair.png'))
        rows.append(row)
    # Rows are stored bottom to top: view 0 goes last to be drawn on top.
    gap = np.zeros((4, rows[0].shape[1], 3))
    sheet = np.concatenate([x for r in reversed(rows) for x in (r, gap)][:-1], axis=0)
    save_png(sheet, os.path.join(o.dir, f'{o.name}_sheet.png'))
    result = {
        'name': o.name, 'input': os.path.abspath(o.input), 'output': os.path.abspath(o.output),
        'engine': 'CYCLES', 'samples': o.samples, 'size': o.size,
        'center': list(center), 'radius': radius,
        'mean_abs_diff': float(np.mean([v['mean_abs_diff'] for v in views])),
        'floor': float(np.mean([v['floor'] for v in views])) if floors else None,
        'views': views, 'input_info': info_in, 'output_info': info_out,
        'seconds': round(time.time() - t0, 1),
    }
    with open(os.path.join(o.dir, f'{o.name}.json'), 'w') as f:
        json.dump(result, f, indent=1)
    print('RESULT', json.dumps(result))


main()
