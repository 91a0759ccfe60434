#!/usr/bin/env python3
"""Generates lumiere's teaching scenes (glTF 2.0, embedded base64 buffers).

Run from anywhere: `python3 assets/scenes/make_scenes.py`; the files are
written next to this script. Standard library only.

Conventions (docs: /work/shared/course/COURSE.md, lumiere's loader):
* metres, +Y up, linear RGB;
* emissiveFactor x KHR_materials_emissive_strength is radiance (W m^-2 sr^-1),
  emitted from the front face only (counter-clockwise winding seen from the
  side it lights);
* metallic 0 & roughness 1 -> Lambert; metallic 1 & roughness 0 -> mirror;
  KHR_materials_transmission 1 & roughness 0 -> glass of KHR_materials_ior;
  otherwise normalised Phong with kd = base (1 - metallic),
  ks = mix(0.04, base, metallic), n = 2 / alpha^2 - 2, alpha = roughness^2;
* the camera is the first glTF camera (yfov; the aspect comes from the image).

Scenes:
* veach-mis.gltf      Veach's multiple-importance-sampling test picture
* penumbra.gltf       an occluder on a post under a point light (a sphere with --lights area)
* indirect-room.gltf  a closed room whose visible surfaces get no direct light
* cornell-{point,spot,mirror,glossy}.gltf  copies of tests/data/ variants
* cornell-glass.gltf  the Cornell box with a closed glass tall block
"""

import base64
import json
import math
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

ASSET = {
    "version": "2.0",
    "generator": "lumiere assets/scenes/make_scenes.py",
    "copyright": "CC0 1.0",
}

# --------------------------------------------------------------------------
# small vector helpers


def add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def mul(a, s):
    return [a[0] * s, a[1] * s, a[2] * s]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]


def normalize(a):
    length = math.sqrt(dot(a, a))
    return [a[0] / length, a[1] / length, a[2] / length]


def look_at_quaternion(eye, target, up=(0.0, 1.0, 0.0)):
    """Rotation [x, y, z, w] turning the camera's -Z towards target, +Y up."""
    back = normalize(sub(eye, target))  # camera +Z
    right = normalize(cross(list(up), back))
    true_up = cross(back, right)
    # rotation matrix with columns right, true_up, back
    m00, m10, m20 = right
    m01, m11, m21 = true_up
    m02, m12, m22 = back
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = 0.5 / math.sqrt(trace + 1.0)
        w = 0.25 / s
        x = (m21 - m12) * s
        y = (m02 - m20) * s
        z = (m10 - m01) * s
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        w = (m21 - m12) / s
        x = 0.25 * s
        y = (m01 + m10) / s
        z = (m02 + m20) / s
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        w = (m02 - m20) / s
        x = (m01 + m10) / s
        y = 0.25 * s
        z = (m12 + m21) / s
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        w = (m10 - m01) / s
        x = (m02 + m20) / s
        y = (m12 + m21) / s
        z = 0.25 * s
    return [x, y, z, w]


def roughness_for_exponent(n):
    """glTF roughness giving lumiere's Phong exponent n = 2/alpha^2 - 2, alpha = roughness^2."""
    alpha = math.sqrt(2.0 / (n + 2.0))
    return math.sqrt(alpha)


def exponent_for_roughness(roughness):
    alpha = roughness * roughness
    return 2.0 / (alpha * alpha) - 2.0


# --------------------------------------------------------------------------
# geometry: every shape is (positions, normals, indices), triangles
# counter-clockwise seen from the side the normal points to (glTF front face)


class Geometry:
    def __init__(self):
        self.positions = []
        self.normals = []
        self.indices = []

    def extend(self, other):
        base = len(self.positions)
        self.positions += other.positions
        self.normals += other.normals
        self.indices += [base + i for i in other.indices]
        return self

    def quad(self, p0, p1, p2, p3):
        """A planar quad p0 p1 p2 p3, counter-clockwise seen from its front."""
        normal = normalize(cross(sub(p1, p0), sub(p3, p0)))
        base = len(self.positions)
        for p in (p0, p1, p2, p3):
            self.positions.append(list(p))
            self.normals.append(normal)
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]
        return self

    def rect(self, center, u, v):
        """Rectangle center +- u +- v, front face towards u x v."""
        c = center
        return self.quad(
            sub(sub(c, u), v), sub(add(c, u), v), add(add(c, u), v), add(sub(c, u), v)
        )

    def box(self, lo, hi, inward=False, skip=()):
        """Axis-aligned box; faces named -x +x -y +y -z +z may be skipped."""
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        faces = {
            "-x": ([x0, y0, z0], [x0, y0, z1], [x0, y1, z1], [x0, y1, z0]),
            "+x": ([x1, y0, z1], [x1, y0, z0], [x1, y1, z0], [x1, y1, z1]),
            "-y": ([x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]),
            "+y": ([x0, y1, z1], [x1, y1, z1], [x1, y1, z0], [x0, y1, z0]),
            "-z": ([x1, y0, z0], [x0, y0, z0], [x0, y1, z0], [x1, y1, z0]),
            "+z": ([x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]),
        }
        for name, quad in faces.items():
            if name in skip:
                continue
            if inward:
                quad = tuple(reversed(quad))
            self.quad(*quad)
        return self


def uv_sphere(center, radius, segments=32, rings=16):
    """UV sphere, triangles counter-clockwise seen from outside (normals outward)."""
    g = Geometry()
    # vertices: poles plus (rings - 1) latitude circles
    g.positions.append(add(center, [0.0, radius, 0.0]))
    g.normals.append([0.0, 1.0, 0.0])
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            n = [math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)]
            g.positions.append(add(center, mul(n, radius)))
            g.normals.append(n)
    g.positions.append(add(center, [0.0, -radius, 0.0]))
    g.normals.append([0.0, -1.0, 0.0])
    south = len(g.positions) - 1

    def ring(i, j):
        return 1 + (i - 1) * segments + (j % segments)

    for j in range(segments):
        g.indices += [0, ring(1, j), ring(1, j + 1)]
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            g.indices += [a, c, d, a, d, b]
    for j in range(segments):
        g.indices += [south, ring(rings - 1, j + 1), ring(rings - 1, j)]
    # check the winding: every face's normal points away from the centre
    for t in range(0, len(g.indices), 3):
        p0, p1, p2 = (g.positions[k] for k in g.indices[t : t + 3])
        face = cross(sub(p1, p0), sub(p2, p0))
        mid = mul(add(add(p0, p1), p2), 1.0 / 3.0)
        assert dot(face, sub(mid, center)) > 0.0, "sphere triangle wound inwards"
    return g


def mesh_area(g):
    area = 0.0
    for t in range(0, len(g.indices), 3):
        p0, p1, p2 = (g.positions[k] for k in g.indices[t : t + 3])
        c = cross(sub(p1, p0), sub(p2, p0))
        area += 0.5 * math.sqrt(dot(c, c))
    return area


# --------------------------------------------------------------------------
# glTF writer


class Gltf:
    def __init__(self, scene_name, extras=None):
        self.doc = {
            "asset": dict(ASSET),
            "scene": 0,
            "scenes": [{"name": scene_name, "nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "cameras": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        if extras:
            self.doc["asset"]["extras"] = extras
        self.blob = bytearray()
        self.extensions = set()

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        offset = len(self.blob)
        self.blob += data
        view = {"buffer": 0, "byteOffset": offset, "byteLength": len(data), "target": target}
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, accessor):
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def _vec3(self, values, with_bounds):
        data = b"".join(struct.pack("<3f", *v) for v in values)
        accessor = {
            "bufferView": self._view(data, 34962),
            "componentType": 5126,
            "count": len(values),
            "type": "VEC3",
        }
        if with_bounds:
            # bounds of the float32 values actually stored
            stored = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in values]
            accessor["min"] = [min(v[k] for v in stored) for k in range(3)]
            accessor["max"] = [max(v[k] for v in stored) for k in range(3)]
        return self._accessor(accessor)

    def material(self, name, base, metallic=0.0, roughness=1.0, emission=None, extras=None):
        material = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [base[0], base[1], base[2], 1.0],
                "metallicFactor": metallic,
                "roughnessFactor": roughness,
            },
        }
        if emission is not None:
            # emission = radiance per channel; factor normalised to max 1
            strength = max(emission)
            material["emissiveFactor"] = [c / strength for c in emission]
            if strength != 1.0:
                material["extensions"] = {
                    "KHR_materials_emissive_strength": {"emissiveStrength": strength}
                }
                self.extensions.add("KHR_materials_emissive_strength")
        if extras:
            material["extras"] = extras
        self.doc["materials"].append(material)
        return len(self.doc["materials"]) - 1

    def mesh(self, name, geometry, material):
        count = len(geometry.positions)
        if count < 65536:
            index_data = struct.pack("<%dH" % len(geometry.indices), *geometry.indices)
            component = 5123
        else:
            index_data = struct.pack("<%dI" % len(geometry.indices), *geometry.indices)
            component = 5125
        position = self._vec3(geometry.positions, True)
        normal = self._vec3(geometry.normals, False)
        indices = self._accessor(
            {
                "bufferView": self._view(index_data, 34963),
                "componentType": component,
                "count": len(geometry.indices),
                "type": "SCALAR",
                "min": [min(geometry.indices)],
                "max": [max(geometry.indices)],
            }
        )
        self.doc["meshes"].append(
            {
                "name": name,
                "primitives": [
                    {
                        "attributes": {"POSITION": position, "NORMAL": normal},
                        "indices": indices,
                        "material": material,
                        "mode": 4,
                    }
                ],
            }
        )
        return self.node({"name": name, "mesh": len(self.doc["meshes"]) - 1})

    def node(self, node):
        self.doc["nodes"].append(node)
        index = len(self.doc["nodes"]) - 1
        self.doc["scenes"][0]["nodes"].append(index)
        return index

    def camera(self, name, eye, target, yfov, aspect, up=(0.0, 1.0, 0.0)):
        self.doc["cameras"].append(
            {
                "name": name,
                "type": "perspective",
                "perspective": {"yfov": yfov, "aspectRatio": aspect, "znear": 0.01},
            }
        )
        return self.node(
            {
                "name": name,
                "camera": len(self.doc["cameras"]) - 1,
                "translation": list(eye),
                "rotation": look_at_quaternion(eye, target, up),
            }
        )

    def write(self, filename):
        self.doc["buffers"] = [
            {
                "byteLength": len(self.blob),
                "uri": "data:application/octet-stream;base64,"
                + base64.b64encode(bytes(self.blob)).decode("ascii"),
            }
        ]
        if self.extensions:
            self.doc["extensionsUsed"] = sorted(self.extensions)
        for key in ("materials", "cameras"):
            if not self.doc[key]:
                del self.doc[key]
        path = filename if os.path.isabs(filename) else os.path.join(HERE, filename)
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")
        print("wrote %s (%d bytes)" % (path, os.path.getsize(path)))


# --------------------------------------------------------------------------
# 1. Veach's MIS scene


# Phong exponents of the plates, farthest (top of the picture) first. With
# n = 10000, 1000, 100, 10 the nearest plate's lobe (n = 10) is wider than the
# lights' spacing and shows one even band instead of four highlights; a decade
# higher, every plate shows four highlights, as in Veach's figure.
# veach_mis((1e4, 1e3, 1e2, 10.0)) gives the other set.
VEACH_EXPONENTS = (100000.0, 10000.0, 1000.0, 100.0)


def veach_mis(exponents=VEACH_EXPONENTS, filename="veach-mis.gltf"):
    """Veach's glossy-plates picture (thesis, chapter 9, multiple importance sampling), in the layout of
    the widely used re-creation by Steve Marschner (CS667), later in Mitsuba's and
    Bitterli's test scenes: four 8-unit plates, four sphere lights at y = 0,
    z = 0, x = -3.75 .. 3.75, radii 1/30 .. 0.9 in steps of x3, radiance ~ 1/r^2,
    camera at (0, 2, 15) looking at (0, -2, 2.5). Here scaled by S = 0.25 to
    metres (plates 2 m wide); radiances unchanged, so the picture is the same."""
    S = 0.25
    g = Gltf(
        "Veach MIS",
        {
            "title": "Veach's multiple importance sampling test: four glossy plates, four sphere lights of equal power",
            "sources": {
                "layout": "E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD thesis, Stanford, 1997, chapter 9 (multiple importance sampling), the glossy plates figure; coordinates of the common re-creation (Marschner, CS667; Mitsuba and Bitterli test scenes) scaled by 0.25 to metres",
            },
        },
    )
    # plates: (y, z) of their two long edges (Veach units), x in [-4, 4]
    plates = [
        # farthest plate first; each plate's normal is the half vector between
        # the directions to the camera and to the row of lights
        ((-2.70651, 0.25609), (-2.08375, -0.526323)),
        ((-3.28825, 1.36972), (-2.83856, 0.476536)),
        ((-3.73096, 2.70046), (-3.43378, 1.74564)),
        ((-3.99615, 4.0667), (-3.82069, 3.08221)),
    ]
    # farthest (top of the picture) sharpest, nearest (bottom) roughest, as in Veach's figure
    base = [0.8, 0.8, 0.8]
    camera_eye = [0.0, 2.0 * S, 15.0 * S]
    for k, ((ya, za), (yb, zb)) in enumerate(plates):
        n = exponents[k]
        roughness = roughness_for_exponent(n)
        material = g.material(
            "plate %d, Phong n = %g" % (k + 1, n),
            base,
            metallic=1.0,
            roughness=round(roughness, 6),
            extras={
                "phong": "metallic 1: kd = 0, ks = baseColor 0.8; roughness %.6f -> alpha %.6f -> n = 2/alpha^2 - 2 = %.1f"
                % (round(roughness, 6), round(roughness, 6) ** 2, exponent_for_roughness(round(roughness, 6)))
            },
        )
        p_a = [0.0, ya * S, za * S]
        p_b = [0.0, yb * S, zb * S]
        plate = Geometry().quad(
            [-4.0 * S, p_a[1], p_a[2]],
            [4.0 * S, p_a[1], p_a[2]],
            [4.0 * S, p_b[1], p_b[2]],
            [-4.0 * S, p_b[1], p_b[2]],
        )
        # front face towards the camera and the lights
        normal = plate.normals[0]
        if dot(normal, sub(camera_eye, p_a)) < 0.0:
            plate = Geometry().quad(
                [-4.0 * S, p_b[1], p_b[2]],
                [4.0 * S, p_b[1], p_b[2]],
                [4.0 * S, p_a[1], p_a[2]],
                [-4.0 * S, p_a[1], p_a[2]],
            )
        g.mesh("plate %d (n = %g)" % (k + 1, n), plate, material)

    # four sphere lights of equal power: Phi = pi * A * L, A the same multiple of r^2
    radii = [1.0 / 30.0, 0.1, 0.3, 0.9]
    xs = [-3.75, -1.25, 1.25, 3.75]
    radiance_r2 = 1.0  # L r^2 with r in Veach's units (901.803 at r = 0.03333, 100 at r = 0.1, ...)
    powers = []
    for k in range(4):
        r = radii[k] * S
        radiance = radiance_r2 / (radii[k] ** 2)
        sphere = uv_sphere([xs[k] * S, 0.0, 0.0], r, 32, 16)
        area = mesh_area(sphere)
        powers.append(math.pi * area * radiance)
        material = g.material(
            "light %d, r = %.4g m" % (k + 1, r),
            [0.0, 0.0, 0.0],
            emission=[radiance] * 3,
        )
        g.mesh("sphere light %d (r = %.4g m)" % (k + 1, r), sphere, material)
    assert max(powers) / min(powers) - 1.0 < 1e-9
    g.doc["asset"]["extras"]["lights"] = (
        "emissive UV spheres (32 x 16), radii %s m, radiance L = %s W/m^2/sr (L r^2 = %g with r in Veach's units), "
        "so each emits Phi = pi A L = %.4f W (A the tessellated area, %.4f of 4 pi r^2); one-sided, facing out"
        % (
            ", ".join("%.5g" % (r * S) for r in radii),
            ", ".join("%.6g" % (radiance_r2 / r**2) for r in radii),
            radiance_r2,
            powers[0],
            area / (4.0 * math.pi * r * r),
        )
    )

    # dark backdrop: floor and back wall, Lambert 0.1 grey
    dark = g.material("dark grey backdrop", [0.1, 0.1, 0.1])
    floor = Geometry().quad(
        [-12.0 * S, -4.2 * S, 20.0 * S],
        [12.0 * S, -4.2 * S, 20.0 * S],
        [12.0 * S, -4.2 * S, -3.0 * S],
        [-12.0 * S, -4.2 * S, -3.0 * S],
    )
    g.mesh("floor", floor, dark)
    wall = Geometry().quad(
        [-12.0 * S, -4.2 * S, -3.0 * S],
        [12.0 * S, -4.2 * S, -3.0 * S],
        [12.0 * S, 12.0 * S, -3.0 * S],
        [-12.0 * S, 12.0 * S, -3.0 * S],
    )
    g.mesh("back wall", wall, dark)

    # camera: Veach's view, horizontal field of view 41 degrees at 4:3
    aspect = 4.0 / 3.0
    hfov = math.radians(41.0108)
    yfov = 2.0 * math.atan(math.tan(hfov / 2.0) / aspect)
    g.camera("camera", camera_eye, [0.0, -2.0 * S, 2.5 * S], yfov, aspect)
    g.write(filename)


# --------------------------------------------------------------------------
# 2. penumbra


def penumbra():
    g = Gltf(
        "Penumbra",
        {
            "title": "A cube on a thin post above a white floor, under one point light: a hard shadow, or a penumbra that grows with the light's size",
            "lesson": "as authored the light is a point: a hard shadow. --lights area makes it a sphere of radius r (--light-radius) with the same power: the penumbra's width = light size x (occluder-to-floor distance) / (light-to-occluder distance) grows with r and along the post, away from where it meets the floor",
        },
    )
    white = g.material("white floor", [0.8, 0.8, 0.8])
    grey = g.material("grey occluder", [0.5, 0.5, 0.5])
    g.mesh("floor", Geometry().rect([0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [0.0, 0.0, -5.0]), white)
    # occluder: a 0.4 m cube on a 4 cm post, its top at 1.2 m
    cube = Geometry().box([-0.2, 0.8, -0.2], [0.2, 1.2, 0.2])
    post = Geometry().box([-0.02, 0.0, -0.02], [0.02, 0.8, 0.02], skip=("-y", "+y"))
    g.mesh("cube", cube, grey)
    g.mesh("post", post, grey)
    # light: a point at 2.4 m, to the left and behind; 12.5 W/sr is the
    # intensity straight down of a 0.5 m square emitter of radiance 50 W/m^2/sr
    position = [-0.8, 2.4, -0.6]
    intensity = 12.5
    g.extensions.add("KHR_lights_punctual")
    g.doc["extensions"] = {
        "KHR_lights_punctual": {
            "lights": [{"name": "lamp", "type": "point", "color": [1.0, 1.0, 1.0], "intensity": intensity}]
        }
    }
    g.node({"name": "lamp", "translation": position, "extensions": {"KHR_lights_punctual": {"light": 0}}})
    g.doc["asset"]["extras"]["light"] = (
        "point light at %s, intensity %g W/sr: power 4 pi I = %.1f W (a sphere of the same power with --lights area)"
        % (position, intensity, 4.0 * math.pi * intensity)
    )
    g.camera("camera", [2.4, 1.9, 3.6], [0.25, 0.45, 0.1], math.radians(42.0), 4.0 / 3.0)
    g.write("penumbra.gltf")


# --------------------------------------------------------------------------
# 3. indirect room


def indirect_room():
    # room x in [-2, 2], y in [0, 2.6], z in [-3, 3]; the camera near the front wall z = 3
    X, Y, Z = 2.0, 2.6, 3.0
    g = Gltf(
        "Indirect room",
        {
            "title": "A closed room lit only by a lamp behind the camera that faces the wall behind the camera",
            "lesson": "the lamp (one-sided) faces the front wall, behind the camera; every surface the camera sees lies behind the lamp's plane, so L1 is black on every visible pixel and the picture is L2 (light from the front wall, lit directly) and L3+",
        },
    )
    grey = g.material("light grey", [0.7, 0.7, 0.7])
    blue = g.material("blue wall", [0.15, 0.3, 0.65])
    floor_m = g.material("floor", [0.6, 0.55, 0.5])
    # inward-facing walls (counter-clockwise seen from inside)
    g.mesh("floor", Geometry().quad([-X, 0, Z], [X, 0, Z], [X, 0, -Z], [-X, 0, -Z]), floor_m)
    g.mesh("ceiling", Geometry().quad([-X, Y, -Z], [X, Y, -Z], [X, Y, Z], [-X, Y, Z]), grey)
    g.mesh("back wall", Geometry().quad([-X, 0, -Z], [X, 0, -Z], [X, Y, -Z], [-X, Y, -Z]), grey)
    g.mesh("left wall (blue)", Geometry().quad([-X, 0, Z], [-X, 0, -Z], [-X, Y, -Z], [-X, Y, Z]), blue)
    g.mesh("right wall", Geometry().quad([X, 0, -Z], [X, 0, Z], [X, Y, Z], [X, Y, -Z]), grey)
    g.mesh("front wall (behind the camera)", Geometry().quad([X, 0, Z], [-X, 0, Z], [-X, Y, Z], [X, Y, Z]), grey)
    # the lamp: a panel facing +z, towards the front wall, behind the camera
    width, height = LAMP_SIZE
    radiance = LAMP_RADIANCE
    colour = [1.0, 0.9, 0.75]
    lamp_m = g.material("lamp", [0.0, 0.0, 0.0], emission=[radiance * c for c in colour])
    lamp_center = [0.0, LAMP_HEIGHT, Z - LAMP_GAP]
    lamp = Geometry().rect(lamp_center, [width / 2, 0.0, 0.0], [0.0, height / 2, 0.0])
    assert lamp.normals[0][2] > 0.99
    g.mesh("lamp (faces the front wall)", lamp, lamp_m)
    # blocks on the floor, to cast soft indirect shadows
    g.mesh("block", Geometry().box([-0.9, 0.0, -1.4], [0.1, 0.9, -0.6], skip=("-y",)), grey)
    g.mesh("tall block", Geometry().box([0.6, 0.0, -2.4], [1.3, 1.7, -1.7], skip=("-y",)), grey)
    eye = [0.0, 1.5, lamp_center[2] - 0.25]
    g.doc["asset"]["extras"]["light"] = (
        "one-sided emissive panel %g x %g m centred at %s, facing +z (the front wall, %g m away), radiance (%s) W/m^2/sr, "
        "power pi A L = %.0f W (of the red channel); the camera at z = %g looks towards -z, so every surface it sees lies behind the panel's plane"
        % (width, height, lamp_center, LAMP_GAP, ", ".join("%g" % (radiance * c) for c in colour),
           math.pi * width * height * radiance, eye[2])
    )
    g.camera("camera", eye, [0.0, 1.0, -Z], math.radians(60.0), 4.0 / 3.0)
    g.write("indirect-room.gltf")


LAMP_SIZE = (0.6, 0.4)
LAMP_RADIANCE = 300.0
LAMP_HEIGHT = 1.7
LAMP_GAP = 0.8


# --------------------------------------------------------------------------
# 4. Cornell variants: plain copies of the test scenes


def cornell_copies():
    for name in ("cornell-point", "cornell-spot", "cornell-mirror", "cornell-glossy"):
        source = os.path.join(REPO, "tests", "data", name + ".gltf")
        target = os.path.join(HERE, name + ".gltf")
        shutil.copyfile(source, target)
        print("copied %s -> %s" % (source, target))


# --------------------------------------------------------------------------
# 5. the Cornell box with a glass block


def cornell_glass():
    """The built-in Cornell box (assets/cornell-box.gltf) with its tall block
    made of clear glass (ior 1.5): the published block's four sides and top,
    plus a bottom face so that the block is closed, lifted 1 mm off the
    floor so that its bottom and the floor do not coincide. The other
    meshes, materials, light and camera are the box's, unchanged."""
    source = os.path.join(REPO, "assets", "cornell-box.gltf")
    with open(source) as f:
        original = json.load(f)
    blob = bytearray(base64.b64decode(original["buffers"][0]["uri"].split(",", 1)[1]))
    names = [m["name"] for m in original["meshes"]]
    tall = names.index("tall block")
    accessor = original["accessors"][original["meshes"][tall]["primitives"][0]["attributes"]["POSITION"]]
    view = original["bufferViews"][accessor["bufferView"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    corners = set(struct.unpack_from("<3f", blob, start + 12 * i) for i in range(accessor["count"]))
    bottom = [c for c in corners if c[1] == 0.0]
    top_y = max(c[1] for c in corners)
    # the footprint in order around its centre
    cx = sum(c[0] for c in bottom) / 4.0
    cz = sum(c[2] for c in bottom) / 4.0
    bottom.sort(key=lambda c: math.atan2(c[2] - cz, c[0] - cx))
    lift = 0.001
    low = [[c[0], lift, c[2]] for c in bottom]
    high = [[c[0], top_y, c[2]] for c in bottom]
    centre = [cx, (lift + top_y) / 2.0, cz]
    block = Geometry()

    def face(p0, p1, p2, p3):
        # wind each quad so that its front (normal) faces away from the centre
        if dot(cross(sub(p1, p0), sub(p3, p0)), sub(p0, centre)) < 0.0:
            p0, p1, p2, p3 = p3, p2, p1, p0
        block.quad(p0, p1, p2, p3)

    for i in range(4):
        j = (i + 1) % 4
        face(low[i], low[j], high[j], high[i])
    face(*high)
    face(*low)

    g = Gltf("Cornell box, glass tall block")
    g.blob = blob
    for key in ("accessors", "bufferViews", "materials", "cameras"):
        g.doc[key] = original[key]
    g.doc["meshes"] = [m for i, m in enumerate(original["meshes"]) if i != tall]
    for node in original["nodes"]:
        if node.get("mesh") == tall:
            continue
        node = dict(node)
        if node.get("mesh", -1) > tall:
            node["mesh"] -= 1
        g.node(node)
    g.doc["materials"].append(
        {
            "name": "glass",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.0,
            },
            "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.5},
            },
        }
    )
    g.mesh("glass block", block, len(g.doc["materials"]) - 1)
    extras = dict(original["asset"].get("extras", {}))
    extras["title"] = "Cornell box, glass tall block"
    extras["sources"] = dict(extras.get("sources", {}))
    extras["sources"]["glass"] = (
        "the tall block of the published data, closed by a bottom face and lifted 1 mm off the floor, "
        "made of clear glass: KHR_materials_transmission 1, KHR_materials_ior 1.5, roughness 0, base colour white"
    )
    g.doc["asset"]["extras"] = extras
    g.extensions = set(original.get("extensionsUsed", [])) | {
        "KHR_materials_transmission",
        "KHR_materials_ior",
    }
    g.write("cornell-glass.gltf")


if __name__ == "__main__":
    veach_mis()
    penumbra()
    indirect_room()
    cornell_copies()
    cornell_glass()
