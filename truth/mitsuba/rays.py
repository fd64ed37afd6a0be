#!/usr/bin/env python3
"""Mitsuba 3's ray casts on the scenes `harness export-scene` writes: the first four ray sets of
`harness rays` (truth::throughput; the fifth, the reference's own photon paths, has no
counterpart here), on the same number of threads, so the reference's BVH can be
set beside Mitsuba's (Embree, through its llvm variant) as a ratio.

    pip install mitsuba numpy
    harness export-scene cornell-sphere --out glb/cornell-sphere.glb      # one file per scene
    python3 truth/mitsuba/rays.py --threads 2 --ours truth/docs/speed.md \\
        --markdown truth/docs/mitsuba.md glb/*.glb

The sets, each one ray per pixel of a --size image (random sets: as many rays):
- coherent closest-hit: a ray through each pixel centre of the file's camera (as scene::Camera::ray);
- incoherent closest-hit: rays from random points in the scene's bounds, directions uniform on
  the sphere;
- coherent any-hit: from each camera ray's first surface, pushed off it by 1e-4 max(1, |p|)
  toward the ray's side, to the file's first light (the same rays as the reference's set:
  the table's hit counts show it);
- incoherent any-hit: segments between two random points of the bounds.
Each set is cast --rounds times after one warm-up round (Dr.Jit compiles a kernel the first
time); the table gives the median round's millions of rays per second, and with --ours the
ratio of Mitsuba's to the reference's median from `harness rays`' table for the same scene.
"""

import argparse
import json
import math
import os
import platform
import struct
import sys
import time

import numpy as np

COMPONENT = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def read_glb(path):
    """The JSON document and the binary chunk of a .glb file."""
    data = open(path, "rb").read()
    magic, _version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67:
        sys.exit(f"error: {path} is not a binary glTF file")
    offset, doc, blob = 12, None, b""
    while offset < length:
        size, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8 : offset + 8 + size]
        offset += 8 + size
        if kind == 0x4E4F534A:
            doc = json.loads(chunk)
        elif kind == 0x004E4942:
            blob = chunk
    return doc, blob


def accessor(doc, blob, index):
    """An accessor's elements as an (count, width) array (tightly packed views only, as the
    workspace's exporter writes them)."""
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    dtype = COMPONENT[a["componentType"]]
    width = WIDTH[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = view.get("byteStride", 0)
    if stride and stride != np.dtype(dtype).itemsize * width:
        sys.exit("error: interleaved vertex data is not read by this script")
    values = np.frombuffer(blob, dtype=dtype, count=a["count"] * width, offset=start)
    return values.reshape(a["count"], width)


def local_matrix(node):
    """A node's transform (column-major glTF) as a 4x4 row-major numpy matrix."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = r * s
    m[:3, 3] = t
    return m


def world_nodes(doc):
    """(node, world matrix) for every node of the default scene."""
    out = []

    def visit(index, parent):
        node = doc["nodes"][index]
        world = parent @ local_matrix(node)
        out.append((node, world))
        for child in node.get("children", []):
            visit(child, world)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(root, np.eye(4))
    return out


def scene_of(path):
    """World triangles (positions, indices per mesh), the camera and the first light."""
    doc, blob = read_glb(path)
    meshes, camera, light = [], None, None
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for node, world in world_nodes(doc):
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                p = accessor(doc, blob, prim["attributes"]["POSITION"]).astype(np.float64)
                p = (np.c_[p, np.ones(len(p))] @ world.T)[:, :3]
                i = accessor(doc, blob, prim["indices"]).astype(np.uint32).reshape(-1, 3)
                meshes.append((p.astype(np.float32), i))
        if "camera" in node and camera is None:
            camera = (doc["cameras"][node["camera"]], world)
        ext = node.get("extensions", {}).get("KHR_lights_punctual")
        if ext is not None and light is None:
            light = (lights[ext["light"]], world)
    if camera is None:
        sys.exit(f"error: {path} has no camera")
    return meshes, camera, light


def camera_rays(camera, size):
    """One ray through each pixel centre, row 0 at the top (scene::Camera::ray)."""
    cam, world = camera
    eye, right, up = world[:3, 3], world[:3, 0], world[:3, 1]
    forward = -world[:3, 2]
    right, up, forward = (v / np.linalg.norm(v) for v in (right, up, forward))
    w, h = size
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    sx, sy = (2 * x / w - 1).ravel(), (1 - 2 * y / h).ravel()
    aspect = w / h
    if cam["type"] == "orthographic":
        half = cam["orthographic"]["ymag"]
        o = eye + np.outer(sx * half * aspect, right) + np.outer(sy * half, up)
        d = np.tile(forward, (len(sx), 1))
    else:
        t = math.tan(cam["perspective"]["yfov"] / 2)
        d = forward + np.outer(sx * t * aspect, right) + np.outer(sy * t, up)
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        o = np.tile(eye, (len(sx), 1))
    return o, d, np.full(len(sx), np.inf)


def random_sets(low, high, count, seed):
    """Random rays (points in the box, directions uniform on the sphere) and random segments."""
    rng = np.random.default_rng(seed)
    a = low + (high - low) * rng.random((count, 3))
    b = low + (high - low) * rng.random((count, 3))
    d = rng.normal(size=(count, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    seg = b - a
    length = np.linalg.norm(seg, axis=1)
    return (a, d, np.full(count, np.inf)), (a, seg / length[:, None], length)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+", help=".glb files written by harness export-scene")
    parser.add_argument("--size", default="256x256", help="WxH: rays per set")
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--ours", help="the markdown harness rays wrote, for the ratio")
    parser.add_argument("--markdown", help="also write the table here")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(args.threads)

    def ray_of(o, d, maxt):
        ray = mi.Ray3f(
            mi.Point3f(*(mi.Float(o[:, k].astype(np.float32)) for k in range(3))),
            mi.Vector3f(*(mi.Float(d[:, k].astype(np.float32)) for k in range(3))),
        )
        # Set apart: the constructor's third argument is the ray's time, not its length.
        ray.maxt = mi.Float(np.minimum(maxt, 3.0e38).astype(np.float32))
        return ray

    def cast(scene, ray, closest, rounds):
        run = (lambda: scene.ray_intersect_preliminary(ray).t) if closest else (lambda: scene.ray_test(ray))
        result = run()
        dr.eval(result)
        dr.sync_thread()
        seconds = []
        for _ in range(rounds):
            start = time.perf_counter()
            result = run()
            dr.eval(result)
            dr.sync_thread()
            seconds.append(time.perf_counter() - start)
        hits = int(np.count_nonzero(np.array(result) < np.inf)) if closest else int(np.count_nonzero(np.array(result)))
        rate = sorted(dr.width(ray.o) / s / 1e6 for s in seconds)[len(seconds) // 2]
        return rate, hits

    ours = read_ours(args.ours) if args.ours else {}
    rows = []
    for path in args.scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        meshes, camera, light = scene_of(path)
        shapes = {}
        for k, (p, i) in enumerate(meshes):
            mesh = mi.Mesh(f"m{k}", len(p), len(i), has_vertex_normals=False, has_vertex_texcoords=False)
            params = mi.traverse(mesh)
            params["vertex_positions"] = mi.Float(p.ravel())
            params["faces"] = mi.UInt32(i.ravel())
            params.update()
            shapes[f"m{k}"] = mesh
        scene = mi.load_dict({"type": "scene", **shapes})
        triangles = sum(len(i) for _, i in meshes)
        everything = np.concatenate([p for p, _ in meshes])
        low, high = everything.min(axis=0), everything.max(axis=0)
        o, d, maxt = camera_rays(camera, size)
        count = len(o)
        scattered, segments = random_sets(low, high, count, 0x5EED)
        # The eye pass's shadow rays: from each camera ray's first surface to the first light.
        si = scene.ray_intersect(ray_of(o, d, maxt))
        valid = np.array(si.is_valid())
        p = np.stack([np.array(c) for c in (si.p.x, si.p.y, si.p.z)], axis=1)[valid]
        n = np.stack([np.array(c) for c in (si.n.x, si.n.y, si.n.z)], axis=1)[valid]
        facing = np.where((np.sum(n * d[valid], axis=1) < 0)[:, None], n, -n)
        origin = p + facing * (1e-4 * np.maximum(1, np.linalg.norm(p, axis=1)))[:, None]
        shadow = None
        if light is not None:
            spec, world = light
            if spec["type"] == "directional":
                # glTF's directional light shines along its node's -Z: the light lies along +Z.
                to = np.tile(world[:3, 2] / np.linalg.norm(world[:3, 2]), (len(origin), 1))
                shadow = (origin, to, np.full(len(origin), np.inf))
            else:
                seg = world[:3, 3] - origin
                dist = np.linalg.norm(seg, axis=1)
                shadow = (origin, seg / dist[:, None], dist)
        sets = [
            ("coherent closest", (o, d, maxt), True),
            ("incoherent closest", scattered, True),
            ("coherent any", shadow, False),
            ("incoherent any", segments, False),
        ]
        rates, hits = [], []
        for label, rays, closest in sets:
            if rays is None or len(rays[0]) == 0:
                rates.append(None)
                hits.append(None)
                continue
            rate, hit = cast(scene, ray_of(*rays), closest, args.rounds)
            rates.append(rate)
            hits.append((len(rays[0]), hit))
        rows.append((name, triangles, rates, hits, ours.get(name)))

    md = render(rows, args, size, mi, dr)
    sys.stdout.write(md)
    if args.markdown:
        open(args.markdown, "w").write(md)


SET_NAMES = ("coherent closest-hit", "incoherent closest-hit", "coherent any-hit", "incoherent any-hit")


def read_ours(path):
    """Scene -> the four medians of `harness rays`' summary table (0 for an empty set), and the
    (rays, hits) of each of the four sets from its ray-set table, found by the set's name (None
    for a set the table leaves out)."""
    ours = {}
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 10 and cells[1].isdigit():
            try:
                ours[cells[0]] = ([float(c) if c else 0.0 for c in cells[2:6]], [None] * 4)
            except ValueError:
                pass
        elif len(cells) == 7 and cells[2] in ("closest", "any") and cells[0] in ours:
            for k, name in enumerate(SET_NAMES):
                if cells[1].startswith(name):
                    ours[cells[0]][1][k] = (int(cells[3]), int(cells[4]))
    return ours


def render(rows, args, size, mi, dr):
    cpu = platform.processor() or "an unnamed CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    md = "# Mitsuba 3's ray casts on the same scenes\n\n"
    md += (
        f"Written by `python3 truth/mitsuba/rays.py {' '.join(sys.argv[1:])}` with Mitsuba "
        f"{mi.__version__} ({mi.variant()}, Dr.Jit {dr.__version__}) on {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}: "
        f"{args.threads} threads of {cpu}, {size[0] * size[1]} rays per set.\n\n"
    )
    md += "Millions of rays per second (median of the rounds); in brackets, Mitsuba's over the reference's"
    md += " (`harness rays`' table" + (f", {args.ours})" if args.ours else ")") + ".\n\n"
    md += "| scene | triangles | coherent closest | incoherent closest | coherent any | incoherent any |\n"
    md += "| --- | --- | --- | --- | --- | --- |\n"
    for name, triangles, rates, _hits, ours in rows:
        cells = []
        for k, rate in enumerate(rates):
            if rate is None:
                cells.append("")
            elif ours and ours[0][k] > 0:
                cells.append(f"{rate:.2f} ({rate / ours[0][k]:.1f} x)")
            else:
                cells.append(f"{rate:.2f}")
        md += f"| {name} | {triangles} | " + " | ".join(cells) + " |\n"
    md += "\nHits of each set, Mitsuba's against the reference's (\"hits of rays\" where the sets' "
    md += "sizes differ): the coherent sets are the same rays, so their counts agree to the odd "
    md += "ray that grazes an edge; the random sets are drawn alike by two generators.\n\n"
    md += "| scene | coherent closest | incoherent closest | coherent any | incoherent any |\n"
    md += "| --- | --- | --- | --- | --- |\n"
    for name, _triangles, _rates, hits, ours in rows:
        cells = []
        for k, h in enumerate(hits):
            theirs = ours[1][k] if ours else None
            if h is None:
                cells.append("")
            elif theirs is None:
                cells.append(f"{h[1]}")
            elif theirs[0] != h[0]:
                cells.append(f"{h[1]} of {h[0]} / {theirs[1]} of {theirs[0]}")
            else:
                cells.append(f"{h[1]} / {theirs[1]}")
        md += f"| {name} | " + " | ".join(cells) + " |\n"
    return md


if __name__ == "__main__":
    main()
