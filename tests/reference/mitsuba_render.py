#!/usr/bin/env python3
"""Render a lumiere glTF scene with Mitsuba 3, as an independent reference.

Reads the glTF subset lumiere's test scenes use and renders it with
Mitsuba's `path` integrator, without Russian roulette, to a linear RGB
float EXR:

    python tests/reference/mitsuba_render.py SCENE.gltf --max-depth 3 \
        --spp 4096 --width 128 --height 128 --out OUT.exr \
        [--variant llvm_ad_rgb|scalar_rgb] [--png PREVIEW.png] \
        [--brdf lambert|mirror|phong|glass] [--ior ETA] [--sphere-lights RADIUS] [--point-emitters]

`--max-depth` counts path segments, as Mitsuba does: 1 = emitters seen
directly (L0), 2 = L0 + direct lighting (L1), 3 = L0 + L1 + one indirect
bounce (L2).

Supported glTF subset (anything else is rejected, not approximated):
* `.gltf` JSON with buffers as base64 data URIs or files beside it, and
  `.glb`;
* the default scene's node tree, with TRS or `matrix` transforms;
* indexed or non-indexed triangle meshes (mode 4), POSITION and
  optional NORMAL;
* metallic-roughness materials: metallic 0 and roughness 1 -> Lambert
  (`twosided` `diffuse`, reflectance = baseColor); metallic 1 and
  roughness 0 -> perfect mirror (`twosided` `conductor`, `material:
  none`, specular_reflectance = baseColor); anything else -> lumiere's
  Phong (`lumiere_phong`, registered below);
* KHR_materials_transmission and KHR_materials_ior: a material whose glass
  weight transmissionFactor x (1 - metallic) is 1 -> `dielectric`
  (int_ior = ior, default 1.5, ext_ior = 1, specular_transmittance =
  baseColor); a weight w between 0 and 1 -> `blendbsdf` of weight w between
  the material's other model and that `dielectric`, as lumiere mixes them;
* base colour and emissive textures (PNG or JPEG) at TEXCOORD_0 or
  TEXCOORD_1, one set each (`lumiere_texture`, registered below, reads
  them as lumiere does); KHR_texture_transform is ignored, as lumiere
  ignores it;
* emission: emissiveFactor x KHR_materials_emissive_strength is the
  radiance of a one-sided `area` emitter on the front face (counter-
  clockwise winding); a double-sided one becomes two one-sided copies;
* KHR_lights_punctual point lights (`point`, intensity = color x
  intensity, W/sr), spot lights (`lumiere_spot`, registered below, with
  lumiere's falloff) and directional lights (`directional`, irradiance =
  color x intensity, along the node's -Z);
* the first camera (in node order), perspective or orthographic, looking
  down its -Z; without one, the camera lumiere framed (`--camera`).

lumiere's scene overrides are mirrored, so that both render the
same scene: `--brdf lambert|mirror|phong|glass` (lumiere's `--brdf`: every
material Lambert, a mirror, Phong, or glass of index `--ior`, of
baseColor; emission unchanged) and
`--sphere-lights RADIUS` (lumiere's `--lights area`: every point light
becomes a sphere of that radius, a pure emitter of uniform radiance
I / (pi r^2), the same power 4 pi I). `--point-emitters` is lumiere's
`--lights point`: every emitting mesh becomes cosine points
(`cosine_point`, an emitter registered below).

The pixel filter is a box (each sample uniform inside its pixel), as in
lumiere. The llvm variant needs a libLLVM shared library: set
DRJIT_LIBLLVM_PATH, or let this script look for one in the usual
Debian places.
"""

import argparse
import base64
import glob
import json
import math
import os
import re
import struct
import sys
import time

import numpy as np


# --------------------------------------------------------------------------
# glTF reading
# --------------------------------------------------------------------------

_COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16,
              5125: np.uint32, 5126: np.float32}
_NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


class GltfError(Exception):
    pass


class Gltf:
    def __init__(self, path):
        self.dir = os.path.dirname(os.path.abspath(path))
        self._buffers = {}
        self._binary_chunk = None
        with open(path, "rb") as f:
            data = f.read()
        if data[:4] == b"glTF":
            self.j = self._read_glb(data)
        else:
            self.j = json.loads(data.decode("utf-8"))
        # lumiere's list: it ignores KHR_texture_transform (with a warning), and so does this
        for ext in self.j.get("extensionsRequired", []):
            if ext not in ("KHR_lights_punctual", "KHR_materials_emissive_strength",
                           "KHR_texture_transform"):
                raise GltfError(f"required extension {ext} is not supported")

    def _read_glb(self, data):
        """The JSON of a binary glTF (.glb), keeping its BIN chunk: a
        12-byte header (magic, version 2, length), then chunks of (length,
        type, bytes), the JSON chunk first."""
        if len(data) < 20:
            raise GltfError("the .glb file is shorter than its header")
        magic, version, length = struct.unpack_from("<4sII", data, 0)
        if version != 2:
            raise GltfError(f"glb version {version} is not 2")
        if length > len(data):
            raise GltfError(f"the .glb header says {length} bytes, the file has {len(data)}")
        chunks, offset = [], 12
        while offset + 8 <= length:
            size, kind = struct.unpack_from("<I4s", data, offset)
            body = data[offset + 8:offset + 8 + size]
            if len(body) < size:
                raise GltfError(f"a .glb chunk of {size} bytes runs past the end of the file")
            chunks.append((kind, body))
            offset += 8 + size
        if not chunks or chunks[0][0] != b"JSON":
            raise GltfError("the .glb file does not start with a JSON chunk")
        self._binary_chunk = next((body for kind, body in chunks[1:] if kind == b"BIN\0"), None)
        return json.loads(chunks[0][1].decode("utf-8"))

    def uri_bytes(self, uri, what=""):
        """The bytes a buffer's or image's `uri` names: a base64 data URI, or
        a file beside the glTF; `what` prefixes an error."""
        if uri.startswith("data:"):
            m = re.match(r"data:[^;,]*;base64,(.*)", uri, re.S)
            if not m:
                raise GltfError(f"{what}only base64 data URIs are supported")
            return base64.b64decode(m.group(1))
        from urllib.parse import unquote
        with open(os.path.join(self.dir, unquote(uri)), "rb") as f:
            return f.read()

    def buffer(self, i):
        if i not in self._buffers:
            b = self.j["buffers"][i]
            uri = b.get("uri")
            if uri is None:
                # the .glb's own binary chunk (only buffer 0 may lack a uri)
                if i != 0 or self._binary_chunk is None:
                    raise GltfError(f"buffer {i} has no uri and there is no .glb binary chunk")
                data = self._binary_chunk
            else:
                data = self.uri_bytes(uri)
            if len(data) < b["byteLength"]:
                raise GltfError(f"buffer {i} is shorter than its byteLength")
            self._buffers[i] = data
        return self._buffers[i]

    def accessor(self, i):
        a = self.j["accessors"][i]
        if "sparse" in a:
            raise GltfError("sparse accessors are not supported")
        dtype = np.dtype(_COMPONENT[a["componentType"]])
        n = _NCOMP[a["type"]]
        count = a["count"]
        if "bufferView" not in a:
            return np.zeros((count, n) if n > 1 else count, dtype=dtype)
        v = self.j["bufferViews"][a["bufferView"]]
        data = self.buffer(v["buffer"])
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        elem = dtype.itemsize * n
        stride = v.get("byteStride", elem) or elem
        raw = np.frombuffer(data, dtype=np.uint8, count=stride * (count - 1) + elem, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw, shape=(count, elem), strides=(stride, 1))
        out = np.ascontiguousarray(rows).view(dtype).reshape(count, n)
        if a.get("normalized"):
            raise GltfError("normalized accessors are not supported here")
        return out if n > 1 else out[:, 0]


def _quat_to_mat3(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def node_local_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    r = np.array(node.get("rotation", [0, 0, 0, 1]), dtype=np.float64)
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = _quat_to_mat3(r / np.linalg.norm(r)) @ np.diag(s)
    m[:3, 3] = t
    return m


def world_nodes(g):
    """(node index, world matrix) in depth-first order of the default scene."""
    j = g.j
    nodes = j.get("nodes", [])
    if "scenes" in j and j["scenes"]:
        roots = j["scenes"][j.get("scene", 0)].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    out = []

    def visit(i, parent):
        m = parent @ node_local_matrix(nodes[i])
        out.append((i, m))
        for c in nodes[i].get("children", []):
            visit(c, m)
    for r in roots:
        visit(r, np.eye(4))
    return out


# --------------------------------------------------------------------------
# lumiere's Phong as a Mitsuba BSDF
# --------------------------------------------------------------------------

PHONG_MIN_ALPHA = 1e-4


def phong_exponent(roughness):
    """lumiere's exponent for a glTF roughness: n = 2/alpha^2 - 2, alpha = roughness^2."""
    alpha = max(roughness * roughness, PHONG_MIN_ALPHA)
    return min(max(2.0 / (alpha * alpha) - 2.0, 0.0), 1e6)


def register_phong(mi):
    """Registers `lumiere_phong`: lumiere's normalised modified Phong,
    f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha) (zero past 90 degrees from the
    mirror direction), two-sided, sampled as lumiere samples it (a lobe
    picked by the luminances of kd and ks, then a cosine-weighted direction
    or cos^n around the mirror direction). Parameters: `base` (texture),
    `exponent`, and either `metallic` (kd = base (1 - m), ks = mix(0.04,
    base, m), both scaled so that kd + ks <= 1, as lumiere maps glTF
    materials) or `specular` s (kd = base (1 - s), ks = s: lumiere's
    --brdf phong). Written with Dr.Jit, it is traced into the same kernel
    as Mitsuba's own BSDFs: a Python Lambert made with it rendered the
    Cornell box bit for bit as `diffuse` does, in the same time."""
    import drjit as dr

    class LumierePhong(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.base = props.get_texture("base")
            self.metallic = float(props["metallic"]) if "metallic" in props else 0.0
            self.exponent = float(props["exponent"])
            self.specular = float(props["specular"]) if "specular" in props else -1.0
            flags = (mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.DiffuseReflection
                     | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide)
            self.m_components = [flags]
            self.m_flags = flags

        def lobes(self, si, active):
            base = self.base.eval(si, active)
            if self.specular >= 0.0:
                return base * (1.0 - self.specular), mi.Color3f(self.specular)
            m = self.metallic
            kd = base * (1.0 - m)
            ks = mi.Color3f(0.04) * (1.0 - m) + base * m
            scale = dr.maximum(dr.max(kd + ks), 1.0)
            return kd / scale, ks / scale

        def parts(self, si, wo, active):
            kd, ks = self.lobes(si, active)
            ld, ls = mi.luminance(kd), mi.luminance(ks)
            p_spec = dr.select(ld + ls > 0.0, ls / (ld + ls), 0.0)
            wi = mi.Vector3f(si.wi.x, si.wi.y, dr.abs(si.wi.z))
            flip = si.wi.z < 0.0
            wo_l = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
            return kd, ks, p_spec, wi, wo_l

        def f_pdf(self, kd, ks, p_spec, wi, wo):
            n = self.exponent
            cos_a = dr.dot(wo, mi.Vector3f(-wi.x, -wi.y, wi.z))
            lobe = dr.select(cos_a > 0.0, dr.power(dr.maximum(cos_a, 1e-30), n), 0.0)
            f = kd * dr.inv_pi + ks * ((n + 2.0) * 0.5 * dr.inv_pi) * lobe
            pdf = (1.0 - p_spec) * dr.maximum(wo.z, 0.0) * dr.inv_pi + p_spec * (n + 1.0) * 0.5 * dr.inv_pi * lobe
            valid = (wi.z > 0.0) & (wo.z > 0.0)
            return dr.select(valid, f, 0.0), dr.select(valid, pdf, 0.0)

        def sample(self, ctx, si, sample1, sample2, active):
            kd, ks, p_spec, wi, _ = self.parts(si, si.wi, active)
            n = self.exponent
            specular = sample1 < p_spec
            cos_a = dr.power(sample2.x, 1.0 / (n + 1.0))
            sin_a = dr.safe_sqrt(1.0 - cos_a * cos_a)
            s, c = dr.sincos(2.0 * dr.pi * sample2.y)
            lobe_local = mi.Vector3f(sin_a * c, sin_a * s, cos_a)
            wo_spec = mi.Frame3f(mi.Vector3f(-wi.x, -wi.y, wi.z)).to_world(lobe_local)
            wo_diff = mi.warp.square_to_cosine_hemisphere(sample2)
            wo = dr.select(specular, wo_spec, wo_diff)
            f, pdf = self.f_pdf(kd, ks, p_spec, wi, wo)
            ok = active & (pdf > 0.0)
            flip = si.wi.z < 0.0
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
            bs.pdf = dr.select(ok, pdf, 0.0)
            bs.eta = 1.0
            bs.sampled_component = mi.UInt32(0)
            bs.sampled_type = dr.select(specular, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
            value = dr.select(ok, f * wo.z / dr.maximum(pdf, 1e-30), 0.0)
            return bs, value

        def eval(self, ctx, si, wo, active):
            kd, ks, p_spec, wi, wo_l = self.parts(si, wo, active)
            f, _ = self.f_pdf(kd, ks, p_spec, wi, wo_l)
            return dr.select(active, f * wo_l.z, 0.0)

        def pdf(self, ctx, si, wo, active):
            kd, ks, p_spec, wi, wo_l = self.parts(si, wo, active)
            _, pdf = self.f_pdf(kd, ks, p_spec, wi, wo_l)
            return dr.select(active, pdf, 0.0)

        def eval_pdf(self, ctx, si, wo, active):
            kd, ks, p_spec, wi, wo_l = self.parts(si, wo, active)
            f, pdf = self.f_pdf(kd, ks, p_spec, wi, wo_l)
            return dr.select(active, f * wo_l.z, 0.0), dr.select(active, pdf, 0.0)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"LumierePhong[exponent={self.exponent}]"

    mi.register_bsdf("lumiere_phong", lambda props: LumierePhong(props))


def register_textures(mi):
    """Registers `lumiere_texture`: its `nested` texture read as lumiere
    reads it.

    * `attribute` (optional): the texture coordinates of that mesh
      attribute (u, v, 0 per vertex) instead of the mesh's own. lumiere
      reads a texture at TEXCOORD_0 or TEXCOORD_1, as its glTF reference
      says, and one primitive may use both; a Mitsuba mesh has one set.
    * `area_sampled` (an emissive texture): reported as uniform, so that
      Mitsuba's area emitter picks its light samples uniformly on the
      surface, as lumiere does, and reads the texture there. Otherwise it
      samples the texture's image and maps the uv it drew back onto the
      surface, which misses every part of the surface whose uv lies outside
      [0, 1]² (a repeated texture) and doubles where two parts share a uv."""

    class LumiereTexture(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            self.nested = props["nested"]
            self.attribute = props["attribute"] if "attribute" in props else None
            self.area_sampled = props["area_sampled"] if "area_sampled" in props else False

        def _at(self, si, active):
            if self.attribute is None:
                return si
            moved = mi.SurfaceInteraction3f(si)
            uv = si.shape.eval_attribute_3(self.attribute, si, active)
            moved.uv = mi.Point2f(uv.x, uv.y)
            return moved

        def eval(self, si, active=True):
            return self.nested.eval(self._at(si, active), active)

        def eval_1(self, si, active=True):
            return self.nested.eval_1(self._at(si, active), active)

        def mean(self):
            return self.nested.mean()

        def is_spatially_varying(self):
            return not self.area_sampled

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"LumiereTexture[attribute={self.attribute}, area_sampled={self.area_sampled}]"

    mi.register_texture("lumiere_texture", lambda props: LumiereTexture(props))


def register_emitters(mi):
    """Registers `cosine_point` and `lumiere_spot`, lumiere's point-like
    lights that Mitsuba lacks: Diracs in position, like Mitsuba's `point`,
    which they follow, of radiance I(w) / d^2 towards a point at distance d
    along -w. `cosine_point` is lumiere's `--lights point` light, an area
    light collapsed to its centroid: I(w) = radiance_area * max(0, n.w)
    (|n.w| if two-sided). Mitsuba's own `point` and it rendered a light at
    the same place in the same time (2.5-2.8 s for 128 spp at 256x256,
    both, on a busy machine). `lumiere_spot` is glTF's spot light with
    lumiere's falloff: I t^2, t = (cos - cos_outer) / max(cos_inner -
    cos_outer, 1e-3) clamped to [0, 1], cos the angle to the axis
    (Mitsuba's `spot` ramps linearly in angle, not in cos squared)."""
    import drjit as dr

    class PointLike(mi.Emitter):
        """A Dirac in position at `self.position`, facing `self.normal`,
        whose intensity along a unit direction is `self.intensity(w)`."""

        def __init__(self, props):
            mi.Emitter.__init__(self, props)
            self.position = mi.Point3f(props["position"])
            self.m_flags = mi.EmitterFlags.DeltaPosition

        def towards(self, it):
            """The unit direction from `it` to the light, its distance and the radiance it brings."""
            d = self.position - it.p
            dist = dr.norm(d)
            wi = d / dist
            return wi, dist, self.intensity(-wi) / (dist * dist)

        def sample_direction(self, it, sample, active):
            wi, dist, radiance = self.towards(it)
            ds = dr.zeros(mi.DirectionSample3f)
            ds.p = self.position
            ds.n = self.normal
            ds.d = wi
            ds.dist = dist
            ds.pdf = 1.0
            ds.delta = True
            ds.time = it.time
            ds.emitter = mi.EmitterPtr(self)
            return ds, dr.select(active, radiance, 0.0)

        def pdf_direction(self, it, ds, active):
            return mi.Float(0.0)

        def eval_direction(self, it, ds, active):
            return dr.select(active, self.towards(it)[2], 0.0)

        def eval(self, si, active):
            return mi.Color3f(0.0)

        def traverse(self, callback):
            pass

    class CosinePoint(PointLike):
        def __init__(self, props):
            PointLike.__init__(self, props)
            self.normal = mi.Vector3f(props["normal"])
            self.radiance_area = mi.Color3f(props["radiance_area"])
            self.two_sided = bool(props["two_sided"]) if "two_sided" in props else False

        def intensity(self, direction):
            cos = dr.dot(self.normal, direction)
            return self.radiance_area * (dr.abs(cos) if self.two_sided else dr.maximum(cos, 0.0))

        def to_string(self):
            return "CosinePoint"

    class Spot(PointLike):
        def __init__(self, props):
            PointLike.__init__(self, props)
            self.normal = mi.Vector3f(props["axis"])
            self.peak = mi.Color3f(props["intensity"])
            self.cos_outer = float(props["cos_outer"])
            self.ramp = 1.0 / max(float(props["cos_inner"]) - self.cos_outer, 1e-3)

        def intensity(self, direction):
            t = dr.clip((dr.dot(self.normal, direction) - self.cos_outer) * self.ramp, 0.0, 1.0)
            return self.peak * (t * t)

        def to_string(self):
            return "LumiereSpot"

    mi.register_emitter("cosine_point", lambda props: CosinePoint(props))
    mi.register_emitter("lumiere_spot", lambda props: Spot(props))


def cosine_points(positions, faces, radiance, two_sided):
    """lumiere's `--lights point` for one emitting primitive: one cosine
    point at the area-weighted centroid if the triangles are coplanar
    (normals within 1e-5 of the first's), else one per triangle; each
    carries radiance x area."""
    corners = positions[faces]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    areas = 0.5 * np.linalg.norm(cross, axis=1)
    keep = areas > 0.0
    corners, cross, areas = corners[keep], cross[keep], areas[keep]
    if len(areas) == 0:
        return []
    normals = cross / np.linalg.norm(cross, axis=1, keepdims=True)
    planar = bool(np.all(normals @ normals[0] > 1.0 - 1e-5))
    parts = [np.arange(len(areas))] if planar else [np.array([i]) for i in range(len(areas))]
    lights = []
    for part in parts:
        area = float(areas[part].sum())
        centroid = (areas[part, None] * corners[part].mean(axis=1)).sum(axis=0) / area
        lights.append({"type": "cosine_point", "position": centroid.tolist(),
                       "normal": normals[part[0]].tolist(),
                       "radiance_area": [float(c) * area for c in radiance],
                       "two_sided": two_sided})
    return lights


# --------------------------------------------------------------------------
# Scene conversion
# --------------------------------------------------------------------------

def material_info(g, index, brdf=None):
    """Returns (kind, rgb, emission rgb or None, double_sided, its textures);
    kind is "lambert", "mirror", ("phong", parameters of `lumiere_phong`),
    ("glass", ior) or ("blend", glass weight, the other kind, ior).
    `brdf` ("lambert", "mirror", ("phong", exponent, specular), lumiere's
    --brdf phong, or ("glass", ior), lumiere's --brdf glass) replaces every
    material's model."""
    if index is None:
        mat = {}  # glTF default material: white, metallic 1, roughness 1
    else:
        mat = g.j["materials"][index]
    pbr = mat.get("pbrMetallicRoughness", {})
    # lumiere ignores the metallic-roughness, normal and occlusion textures
    # (it warns), and so does this conversion: both render the same scene
    # lumiere ignores KHR_texture_transform, its offsets, rotations, scales
    # and uv set alike (it warns): so does this
    texture = pbr.get("baseColorTexture")
    emission_texture = mat.get("emissiveTexture")
    base = [float(c) for c in pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]]
    metallic = float(pbr.get("metallicFactor", 1.0))
    roughness = float(pbr.get("roughnessFactor", 1.0))
    extensions = mat.get("extensions", {})
    transmission = float(extensions.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0))
    # lumiere raises an index below 1 to 1 (it warns)
    ior = max(float(extensions.get("KHR_materials_ior", {}).get("ior", 1.5)), 1.0)
    glass = min(max(transmission, 0.0), 1.0) * (1.0 - min(max(metallic, 0.0), 1.0))
    if isinstance(brdf, tuple) and brdf[0] == "glass":
        kind = brdf
    elif isinstance(brdf, tuple):
        _, exponent, specular = brdf
        kind = ("phong", {"exponent": exponent, "specular": specular})
    elif brdf is None and glass >= 1.0:
        kind = ("glass", ior)
    elif brdf is not None:
        kind = brdf
    elif metallic <= 0.0 and roughness >= 1.0:
        kind = "lambert"
    elif metallic >= 1.0 and roughness <= 0.0:
        kind = "mirror"
    else:
        # lumiere's mapping of every other material (COURSE.md)
        kind = ("phong", {"exponent": phong_exponent(roughness),
                          "metallic": min(max(metallic, 0.0), 1.0)})
    if brdf is None and 0.0 < glass < 1.0:
        kind = ("blend", glass, kind, ior)
    strength = float(mat.get("extensions", {}).get("KHR_materials_emissive_strength", {})
                     .get("emissiveStrength", 1.0))
    emission = [float(c) * strength for c in mat.get("emissiveFactor", [0, 0, 0])]
    if max(emission) <= 0.0:
        emission = None
    if emission is None:
        emission_texture = None  # no effect, as in lumiere
    textures = {"base": texture, "emission": emission_texture}
    return kind, base, emission, bool(mat.get("doubleSided", False)), textures


def texture_uv_set(texture):
    """The texture coordinates (0 or 1) glTF texture reference `texture`
    reads, as lumiere reads them: its texCoord; a set above 1 falls back to
    set 0, with lumiere's warning."""
    uv_set = int(texture.get("texCoord", 0))
    if uv_set > 1:
        print(f"warning: a texture reads TEXCOORD_{uv_set}; only sets 0 and 1 are loaded, set 0 used",
              file=sys.stderr)
        return 0
    return uv_set


_WRAP = {10497: "repeat", 33648: "mirror", 33071: "clamp"}


def image_bytes(g, index):
    """The encoded bytes (PNG or JPEG) of glTF image `index`."""
    image = g.j["images"][index]
    if "bufferView" in image:
        view = g.j["bufferViews"][image["bufferView"]]
        start = view.get("byteOffset", 0)
        return g.buffer(view["buffer"])[start:start + view["byteLength"]]
    return g.uri_bytes(image.get("uri", ""), f"image {index}: ")


def texture_bitmap(mi, g, texture, factor):
    """A Mitsuba `bitmap` of glTF texture reference `texture` (a base colour
    or an emissive texture) times its `factor`: decoded to linear RGB (sRGB
    colour texels), then filtered bilinearly in linear values, as lumiere
    does; glTF's uv (0, 0) is the image's top-left corner, as Mitsuba's is."""
    import tempfile
    tex = g.j["textures"][texture["index"]]
    if "source" not in tex:
        raise GltfError(f"texture {texture['index']} has no source image")
    sampler = g.j.get("samplers", [])[tex["sampler"]] if "sampler" in tex else {}
    wrap_s, wrap_t = sampler.get("wrapS", 10497), sampler.get("wrapT", 10497)
    if wrap_s != wrap_t or wrap_s not in _WRAP:
        raise GltfError(f"texture {texture['index']}: wrap modes {wrap_s}, {wrap_t} differ per axis; "
                        "Mitsuba's bitmap has one")
    data = image_bytes(g, tex["source"])
    with tempfile.NamedTemporaryFile(suffix=".img") as f:
        f.write(data)
        f.flush()
        bitmap = mi.Bitmap(f.name)
    # 8-bit colour texels are sRGB-encoded: linear values, as lumiere keeps them
    linear = bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    texels = np.array(linear, dtype=np.float32)[:, :, :3] * np.array(factor, dtype=np.float32)
    return {"type": "bitmap", "bitmap": mi.Bitmap(texels, pixel_format=mi.Bitmap.PixelFormat.RGB),
            "raw": True, "filter_type": "bilinear", "wrap_mode": _WRAP[wrap_s]}


def bsdf_dict(kind, rgb, texture=None):
    color = {"type": "rgb", "value": rgb} if texture is None else texture
    if isinstance(kind, tuple) and kind[0] == "glass":
        # reflection untinted, refraction tinted by the base colour; the
        # front face (the normal's side) is the outside, of index 1
        return {"type": "dielectric", "int_ior": float(kind[1]), "ext_ior": 1.0,
                "specular_transmittance": color}
    if isinstance(kind, tuple) and kind[0] == "blend":
        _, weight, other, ior = kind
        return {"type": "blendbsdf", "weight": float(weight),
                "bsdf_0": bsdf_dict(other, rgb, texture), "bsdf_1": bsdf_dict(("glass", ior), rgb, texture)}
    if isinstance(kind, tuple):
        return dict(kind[1], type="lumiere_phong", base=color)  # two-sided itself
    if kind == "lambert":
        inner = {"type": "diffuse", "reflectance": color}
    else:
        inner = {"type": "conductor", "material": "none", "specular_reflectance": color}
    return {"type": "twosided", "material": inner}


def double_sided_copies(positions, faces, texcoords, attributes=None):
    """A double-sided emitter as two one-sided ones: the triangles as
    given, moved a hair's breadth along their front normal, and the same
    triangles wound the other way, moved as far behind. A ray from either
    side meets first the copy that faces it, whose emission is lumiere's
    double-sided emission; a light sample of the copy behind is dark (it
    faces away) and occluded. The hair is 10⁻⁵ of the mesh's extent and
    distance from the origin, far above float rounding and far below any
    feature of the image."""
    corners = positions[faces]  # (n, 3 vertices, xyz)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    extent = np.ptp(positions, axis=0).max() + np.abs(positions).max()
    hair = 1e-5 * extent * normal[:, None, :]
    n = len(faces)
    unshared = np.arange(3 * n).reshape(n, 3)
    uv = None if texcoords is None else texcoords[faces].reshape(-1, 2)
    extra = {k: a[faces].reshape(-1, a.shape[1]) for k, a in (attributes or {}).items()}
    front = ((corners + hair).reshape(-1, 3), unshared, uv, extra)
    back = ((corners - hair).reshape(-1, 3), unshared[:, [0, 2, 1]], uv, extra)
    return front, back


def build_mesh(mi, name, positions, normals, faces, bsdf, emission, texcoords=None, attributes=None):
    """A Mitsuba mesh from world-space arrays. Emitting meshes get no vertex
    normals, so that Mitsuba's emitting side is the one given by the winding
    (its face normal is cross(p1 - p0, p2 - p0), glTF's front face).
    `attributes`: per-vertex texture coordinates of other sets, by
    attribute name, stored as (u, v, 0) for `uv_set`."""
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if emission is not None:
        radiance = emission if isinstance(emission, dict) else {"type": "rgb", "value": emission}
        props["emitter"] = mi.load_dict({"type": "area", "radiance": radiance})
        normals = None
    mesh = mi.Mesh(name, len(positions), len(faces), props=props, has_vertex_normals=normals is not None,
                   has_vertex_texcoords=texcoords is not None)
    params = mi.traverse(mesh)

    def put(key, array, dtype):
        # The buffers' own array types (dynamic arrays, also in scalar variants).
        params[key] = type(params[key])(np.ascontiguousarray(array, dtype=dtype).ravel())
    put("vertex_positions", positions, np.float32)
    put("faces", faces, np.uint32)
    if normals is not None:
        put("vertex_normals", normals, np.float32)
    if texcoords is not None:
        put("vertex_texcoords", texcoords, np.float32)
    params.update()
    for key, uv in (attributes or {}).items():
        padded = np.zeros((len(uv), 3), dtype=np.float32)
        padded[:, :2] = uv
        mesh.add_attribute(key, 3, type(params["vertex_positions"])(padded.ravel()))
    return mesh


def point_light(position, intensity, sphere_radius):
    """A point light of `intensity` (W/sr), or with `sphere_radius` the sphere
    light of the same power: uniform radiance I / (pi r^2) leaving a sphere
    that reflects nothing."""
    if sphere_radius is None:
        return {"type": "point", "position": position, "intensity": {"type": "rgb", "value": intensity}}
    radiance = [c / (math.pi * sphere_radius * sphere_radius) for c in intensity]
    return {"type": "sphere", "center": position, "radius": sphere_radius,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}},
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": radiance}}}


def convert(mi, g, width, height, spp, max_depth, verbose=True, brdf=None, sphere_radius=None,
            rr_depth=None, given_camera=None, point_emitters=False):
    """The Mitsuba scene dict of glTF `g`. `point_emitters`: lumiere's
    `--lights point`, every emitting primitive replaced by cosine points
    (its triangles gone, as lumiere hides them). `rr_depth` is Mitsuba's: Russian
    roulette after that many interactions (None: none). `given_camera`, a
    (world-from-camera 4x4, yfov) pair in glTF's camera convention, stands
    in for a file without a camera (lumiere then frames the scene itself)."""
    j = g.j
    scene = {"type": "scene"}
    camera = None
    n_emitters = 0
    lights = j.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for ni, world in world_nodes(g):
        node = j["nodes"][ni]
        nname = node.get("name", f"node{ni}")
        if "camera" in node and camera is None:
            camera = (node["camera"], world, nname)
        if "mesh" in node:
            mesh = j["meshes"][node["mesh"]]
            lin = world[:3, :3]
            flip = np.linalg.det(lin) < 0  # a mirroring transform swaps the front face
            nmat = np.linalg.inv(lin).T
            for pi, prim in enumerate(mesh["primitives"]):
                if prim.get("mode", 4) != 4:
                    raise GltfError(f"{nname}: only triangle lists (mode 4) are supported")
                pos = g.accessor(prim["attributes"]["POSITION"]).astype(np.float64)
                pos = pos @ lin.T + world[:3, 3]
                if "indices" in prim:
                    idx = g.accessor(prim["indices"]).astype(np.int64)
                else:
                    idx = np.arange(len(pos))
                faces = idx.reshape(-1, 3)
                if flip:
                    faces = faces[:, [0, 2, 1]]
                nrm = None
                if "NORMAL" in prim["attributes"]:
                    nrm = g.accessor(prim["attributes"]["NORMAL"]).astype(np.float64) @ nmat.T
                    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
                kind, rgb, emission, double_sided, textures = material_info(g, prim.get("material"), brdf)
                used = {k: t for k, t in textures.items() if t is not None}
                uv_sets = {k: texture_uv_set(t) for k, t in used.items()}
                for uv_set in set(uv_sets.values()):
                    if f"TEXCOORD_{uv_set}" not in prim["attributes"]:
                        raise GltfError(f"{nname}: its texture reads TEXCOORD_{uv_set}, which it lacks")
                # the mesh's own coordinates are the emission's: a light
                # sample's point knows its uv but not its triangle, which a
                # mesh attribute needs; a base colour read at another set
                # reads one (`lumiere_texture`)
                mesh_set = uv_sets.get("emission", uv_sets.get("base"))
                uv, extra = None, {}
                for uv_set in set(uv_sets.values()):
                    coords = g.accessor(prim["attributes"][f"TEXCOORD_{uv_set}"]).astype(np.float64)
                    if uv_set == mesh_set:
                        uv = coords
                    else:
                        extra[f"vertex_uv{uv_set}"] = coords
                color = texture_bitmap(mi, g, used["base"], rgb) if "base" in used else None
                if "base" in used and uv_sets["base"] != mesh_set:
                    color = {"type": "lumiere_texture", "nested": color,
                             "attribute": f"vertex_uv{uv_sets['base']}"}
                radiance = emission
                if "emission" in used:
                    radiance = {"type": "lumiere_texture", "area_sampled": True,
                                "nested": texture_bitmap(mi, g, used["emission"], emission)}
                bsdf = bsdf_dict(kind, rgb, color)
                key = f"mesh{ni}_{pi}"
                if emission is not None and point_emitters:
                    # lumiere scales the radiance by the emissive texture's mean texel
                    mean = [1.0, 1.0, 1.0]
                    if "emission" in used:
                        texels = np.array(radiance["nested"]["bitmap"], dtype=np.float64).reshape(-1, 3)
                        mean = (texels.mean(axis=0) / np.maximum(emission, 1e-30)).tolist()
                    scaled = [e * m for e, m in zip(emission, mean)]
                    for k, light in enumerate(cosine_points(pos, faces, scaled, double_sided)):
                        scene[f"{key}_point{k}"] = light
                        n_emitters += 1
                    continue
                if emission is not None and double_sided:
                    # Mitsuba's area emitter is one-sided: two one-sided copies
                    for side, (p, f, t, a) in zip("ab", double_sided_copies(pos, faces, uv, extra)):
                        scene[f"{key}{side}"] = build_mesh(mi, f"{nname}/{pi}{side}", p, None, f, bsdf,
                                                           radiance, t, a)
                    n_emitters += 2
                else:
                    n_emitters += emission is not None
                    scene[key] = build_mesh(mi, f"{nname}/{pi}", pos, nrm, faces, bsdf, radiance, uv, extra)
                if verbose:
                    print(f"  mesh {nname!r}: {len(faces)} triangles, {kind} {rgb}"
                          + (f", emits {emission}" if emission else ""), file=sys.stderr)
        ext = node.get("extensions", {}).get("KHR_lights_punctual")
        if ext is not None:
            light = lights[ext["light"]]
            value = [float(c) * float(light.get("intensity", 1.0)) for c in light.get("color", [1, 1, 1])]
            kind = light["type"]
            if kind == "point":
                scene[f"light{ni}"] = point_light([float(x) for x in world[:3, 3]], value, sphere_radius)
            elif kind == "spot" and sphere_radius is None:
                spot = light.get("spot", {})
                axis = world[:3, :3] @ np.array([0.0, 0.0, -1.0])
                scene[f"light{ni}"] = {
                    "type": "lumiere_spot", "position": [float(x) for x in world[:3, 3]],
                    "axis": [float(x) for x in axis / np.linalg.norm(axis)], "intensity": value,
                    "cos_inner": math.cos(float(spot.get("innerConeAngle", 0.0))),
                    "cos_outer": math.cos(float(spot.get("outerConeAngle", math.pi / 4)))}
            elif kind == "directional":
                d = world[:3, :3] @ np.array([0.0, 0.0, -1.0])
                scene[f"light{ni}"] = {"type": "directional",
                                       "direction": [float(x) for x in d / np.linalg.norm(d)],
                                       "irradiance": {"type": "rgb", "value": value}}
            elif kind == "spot":
                raise GltfError(f"{nname}: a spot light made a sphere (--sphere-lights) keeps its cone "
                                "in lumiere; Mitsuba's sphere emitters have none")
            else:
                raise GltfError(f"{nname}: {kind} lights are not supported")
            n_emitters += 1
            if verbose:
                print(f"  {kind} light {nname!r}: {value} at {world[:3, 3].tolist()}", file=sys.stderr)
    if camera is None and given_camera is not None:
        world, yfov = given_camera
        j = dict(j, cameras=[{"type": "perspective", "perspective": {"yfov": yfov}}])
        camera = (0, world, "given")
    if camera is None:
        raise GltfError("the scene has no camera")
    if n_emitters == 0:
        print("warning: the scene has no emitter", file=sys.stderr)

    cam_index, cam_world, cam_name = camera
    cam = j["cameras"][cam_index]
    kind = cam.get("type")
    if kind not in ("perspective", "orthographic"):
        raise GltfError(f"camera type {kind!r} is not supported")
    # Mitsuba's camera looks down its +Z with +X to the image's left; glTF's
    # looks down -Z with +X to the right: a 180 degree turn about Y maps one
    # onto the other (no mirroring).
    to_world = cam_world @ np.diag([-1.0, 1.0, -1.0, 1.0])
    # Remove any scale from the camera's frame (glTF cameras ignore it).
    to_world[:3, :3] = to_world[:3, :3] / np.linalg.norm(to_world[:3, :3], axis=0)
    projection = cam[kind]
    aspect = projection.get("aspectRatio")
    if aspect is not None and abs(aspect - width / height) > 1e-3:
        print(f"warning: the camera's aspectRatio {aspect} differs from {width}x{height}; "
              "the film's aspect ratio is used, the vertical extent kept", file=sys.stderr)
    sensor = {
        "near_clip": float(projection.get("znear", 1e-3)),
        "far_clip": float(projection.get("zfar", 1e4)),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "pixel_format": "rgb", "component_format": "float32",
                 "rfilter": {"type": "box"}},
    }
    if kind == "perspective":
        yfov = float(projection["yfov"])
        sensor.update({"type": "perspective", "fov_axis": "y", "fov": math.degrees(yfov)})
        view = f"yfov {math.degrees(yfov):.4f} deg"
    else:
        # lumiere keeps glTF's ymag (half the visible height) and takes the
        # width from the film; Mitsuba's orthographic view spans x in [-1, 1]
        # and y in [-1/aspect, 1/aspect] of its camera space, scaled here
        ymag = float(projection["ymag"])
        if not (math.isfinite(ymag) and ymag > 0.0):
            raise GltfError(f"orthographic camera {cam_name!r}: ymag {ymag} is not positive")
        half_width = ymag * width / height
        to_world = to_world @ np.diag([half_width, half_width, 1.0, 1.0])
        sensor["type"] = "orthographic"
        sensor["near_clip"] = max(sensor["near_clip"], 1e-3)
        view = f"orthographic, {2 * half_width:.4g} x {2 * ymag:.4g} m"
    sensor["to_world"] = mi.ScalarTransform4f(to_world.tolist())
    if verbose:
        print(f"  camera {cam_name!r}: {view}, at {cam_world[:3, 3].tolist()}, "
              f"looking along {(-cam_world[:3, 2]).tolist()}", file=sys.stderr)
    scene["sensor"] = sensor
    if rr_depth is None:
        rr_depth = max(100, max_depth + 1)  # never
    scene["integrator"] = {"type": "path", "max_depth": max_depth,
                           "rr_depth": rr_depth, "hide_emitters": False}
    return scene


# --------------------------------------------------------------------------

def find_libllvm():
    cands = []
    for pat in ("/usr/lib/x86_64-linux-gnu/libLLVM*.so*", "/usr/lib/aarch64-linux-gnu/libLLVM*.so*",
                "/usr/lib/llvm-*/lib/libLLVM*.so*", "/usr/lib64/libLLVM*.so*", "/usr/local/lib/libLLVM*.so*"):
        cands += glob.glob(pat)

    def version(p):
        m = re.search(r"(\d+)(?:\.(\d+))?", os.path.basename(p)) or re.search(r"llvm-(\d+)", p)
        return tuple(int(x) for x in m.groups() if x) if m else (0,)
    cands.sort(key=version, reverse=True)
    return cands[0] if cands else None


def positive_length(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}")
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"a radius must be positive and finite, not {text!r}")
    return value


def camera_argument(text):
    """`--camera`: 13 numbers, a world-from-camera matrix's three rows of four
    (glTF's convention: the camera looks down its -Z, +Y up) and the
    vertical field of view in radians."""
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"not numbers: {text!r}")
    if len(values) != 13 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"13 finite numbers expected, not {text!r}")
    if not 0.0 < values[12] < math.pi:
        raise argparse.ArgumentTypeError(f"yfov {values[12]} is not in (0, pi)")
    world = np.eye(4)
    world[:3, :] = np.array(values[:12]).reshape(3, 4)
    return world, values[12]


def brdf_override(args):
    """The `brdf` argument of `convert` from the parsed override arguments."""
    if args.brdf == "phong":
        return ("phong", args.phong_exponent, args.phong_specular)
    if args.brdf == "glass":
        return ("glass", args.ior)
    return args.brdf


def add_override_arguments(ap):
    """lumiere's scene overrides that Mitsuba can render too."""
    ap.add_argument("--brdf", choices=["lambert", "mirror", "phong", "glass"], default=None,
                    help="every material's model, as lumiere's --brdf (default: as authored)")
    ap.add_argument("--ior", type=float, default=1.5,
                    help="with --brdf glass: the index of refraction, as lumiere's --ior")
    ap.add_argument("--phong-exponent", type=float, default=32.0,
                    help="with --brdf phong: the exponent n, as lumiere's --phong-exponent")
    ap.add_argument("--phong-specular", type=float, default=0.25,
                    help="with --brdf phong: ks, kd = base (1 - ks), as lumiere's --phong-specular")
    ap.add_argument("--sphere-lights", type=positive_length, default=None, metavar="RADIUS",
                    help="point lights become sphere lights of this radius and the same power, "
                         "as lumiere's --lights area")
    ap.add_argument("--point-emitters", action="store_true",
                    help="every emitting mesh becomes cosine points of the same power, "
                         "as lumiere's --lights point")
    ap.add_argument("--camera", type=camera_argument, default=None,
                    metavar="R00,R01,R02,T0,R10,...,T2,YFOV",
                    help="the camera of a file that has none: lumiere's framing camera, "
                         "world from camera by rows (glTF's convention) and yfov in radians")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="lumiere glTF scene (.gltf or .glb)")
    ap.add_argument("--max-depth", type=int, required=True,
                    help="maximum number of path segments (1 = L0, 2 = L0+L1, 3 = L0+L1+L2)")
    ap.add_argument("--spp", type=int, default=4096, help="samples per pixel")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--out", required=True, help="output EXR (linear RGB, float32)")
    ap.add_argument("--variant", default="llvm_ad_rgb", choices=["llvm_ad_rgb", "scalar_rgb"])
    ap.add_argument("--spp-per-pass", type=int, default=None,
                    help="split the samples into passes of this many (default: 256 for llvm, all for scalar); "
                         "passes use different seeds and are averaged")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first pass")
    ap.add_argument("--png", help="also write a preview PNG (clamped, sRGB)")
    ap.add_argument("--quiet", action="store_true")
    add_override_arguments(ap)
    args = ap.parse_args(argv)

    if args.variant.startswith("llvm") and not os.environ.get("DRJIT_LIBLLVM_PATH"):
        lib = find_libllvm()
        if lib:
            os.environ["DRJIT_LIBLLVM_PATH"] = lib
    import mitsuba as mi
    mi.set_variant(args.variant)
    register_phong(mi)
    register_textures(mi)
    register_emitters(mi)

    g = Gltf(args.scene)
    t0 = time.perf_counter()
    scene_dict = convert(mi, g, args.width, args.height, args.spp, args.max_depth, verbose=not args.quiet,
                         brdf=brdf_override(args), sphere_radius=args.sphere_lights,
                         given_camera=args.camera, point_emitters=args.point_emitters)
    scene = mi.load_dict(scene_dict)
    t1 = time.perf_counter()

    per_pass = args.spp_per_pass or (256 if args.variant.startswith("llvm") else args.spp)
    per_pass = max(1, min(per_pass, args.spp))
    if args.spp % per_pass:
        ap.error(f"--spp {args.spp} is not a multiple of the samples per pass {per_pass}")
    passes = args.spp // per_pass
    acc = None
    for k in range(passes):
        img = np.array(mi.render(scene, spp=per_pass, seed=args.seed + k), dtype=np.float64)
        acc = img if acc is None else acc + img
    img = (acc / passes).astype(np.float32)
    t2 = time.perf_counter()

    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    bmp = mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB)
    bmp.write(args.out)
    if args.png:
        bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(args.png)
    mean = img.reshape(-1, 3).mean(axis=0)
    print(f"{args.out}: {args.width}x{args.height}, {args.spp} spp ({passes} passes), max_depth {args.max_depth}, "
          f"{args.variant}; load {t1 - t0:.2f} s, render {t2 - t1:.2f} s; "
          f"mean RGB {mean[0]:.6g} {mean[1]:.6g} {mean[2]:.6g}, overall {mean.mean():.6g}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except GltfError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)
