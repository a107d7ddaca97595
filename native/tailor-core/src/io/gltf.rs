//! glTF 2.0 reader (binary `.glb`, or `.gltf` with external `.bin` buffers), parsed by hand
//! with `serde_json` to avoid the `gltf` crate's dependency tree: meshes, the node hierarchy,
//! skins and animations, evaluated to world-space vertex positions at any time.
//!
//! Evaluation at time `t`:
//!
//! 1. every animated node property is sampled from its channel: `STEP` holds the previous key,
//!    `LINEAR` lerps translation/scale and slerps rotation, `CUBICSPLINE` evaluates the Hermite
//!    spline `(2s³−3s²+1)v₀ + (s³−2s²+s)Δt·b₀ + (−2s³+3s²)v₁ + (s³−s²)Δt·a₁`; times outside
//!    the keys clamp to the first/last key;
//! 2. local matrices `T·R·S` (or the node's `matrix`) are chained from the scene roots into
//!    global matrices `G`;
//! 3. a skinned primitive's vertex is `Σₖ wₖ · G(jointₖ) · IBMₖ · v` (the mesh node's own
//!    transform is ignored, as the specification requires); an unskinned one is `G(node) · v`.
//!
//! All mesh primitives (triangles, strips, fans) of all mesh nodes of the default scene are
//! concatenated into one [`TriMesh`]. Not supported: morph targets (ignored), sparse
//! accessors, `data:` URIs, point and line primitives (skipped).

use std::path::Path;

use glam::{Mat4, Quat, Vec3, Vec4};
use serde::Deserialize;

use super::{read_bytes, TriMesh};
use crate::error::{Result, TailorError};
use crate::files;

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct Root {
    #[serde(default)]
    accessors: Vec<Accessor>,
    #[serde(default)]
    buffer_views: Vec<BufferView>,
    #[serde(default)]
    buffers: Vec<Buffer>,
    #[serde(default)]
    nodes: Vec<JNode>,
    #[serde(default)]
    meshes: Vec<JMesh>,
    #[serde(default)]
    skins: Vec<JSkin>,
    #[serde(default)]
    animations: Vec<JAnimation>,
    #[serde(default)]
    scenes: Vec<JScene>,
    scene: Option<usize>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Accessor {
    buffer_view: Option<usize>,
    #[serde(default)]
    byte_offset: usize,
    component_type: u32,
    #[serde(default)]
    normalized: bool,
    count: usize,
    #[serde(rename = "type")]
    kind: String,
    sparse: Option<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct BufferView {
    buffer: usize,
    #[serde(default)]
    byte_offset: usize,
    byte_length: usize,
    byte_stride: Option<usize>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Buffer {
    uri: Option<String>,
    byte_length: Option<u64>,
}

#[derive(Deserialize, Default)]
struct JNode {
    #[serde(default)]
    children: Vec<usize>,
    matrix: Option<[f32; 16]>,
    translation: Option<[f32; 3]>,
    rotation: Option<[f32; 4]>,
    scale: Option<[f32; 3]>,
    mesh: Option<usize>,
    skin: Option<usize>,
}

#[derive(Deserialize)]
struct JMesh {
    primitives: Vec<JPrimitive>,
}

#[derive(Deserialize)]
struct JPrimitive {
    attributes: std::collections::HashMap<String, usize>,
    indices: Option<usize>,
    mode: Option<u32>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct JSkin {
    joints: Vec<usize>,
    inverse_bind_matrices: Option<usize>,
}

#[derive(Deserialize)]
struct JAnimation {
    name: Option<String>,
    channels: Vec<JChannel>,
    samplers: Vec<JSampler>,
}

#[derive(Deserialize)]
struct JChannel {
    sampler: usize,
    target: JTarget,
}

#[derive(Deserialize)]
struct JTarget {
    node: Option<usize>,
    path: String,
}

#[derive(Deserialize)]
struct JSampler {
    input: usize,
    output: usize,
    interpolation: Option<String>,
}

#[derive(Deserialize)]
struct JScene {
    #[serde(default)]
    nodes: Vec<usize>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Path3 {
    Translation,
    Rotation,
    Scale,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Interp {
    Step,
    Linear,
    Cubic,
}

#[derive(Debug, Clone)]
struct Channel {
    node: usize,
    path: Path3,
    interp: Interp,
    times: Vec<f32>,
    /// Flattened output: `width` floats per key (three keys' worth per key for cubic splines).
    values: Vec<f32>,
}

/// One animation: its name, channels and length in seconds.
#[derive(Debug, Clone)]
pub struct Animation {
    pub name: String,
    pub duration: f32,
    channels: Vec<Channel>,
}

#[derive(Debug, Clone, Copy)]
struct Trs {
    t: Vec3,
    r: Quat,
    s: Vec3,
}

#[derive(Debug, Clone)]
struct Part {
    node: usize,
    skin: Option<usize>,
    positions: Vec<Vec3>,
    joints: Vec<[u32; 4]>,
    weights: Vec<[f32; 4]>,
}

/// A loaded glTF scene, ready to be evaluated at any time.
#[derive(Debug, Clone)]
pub struct GltfScene {
    file: String,
    /// Nodes in parent-before-child order, with their parent.
    order: Vec<(usize, Option<usize>)>,
    rest: Vec<Trs>,
    matrices: Vec<Option<Mat4>>,
    skins: Vec<(Vec<usize>, Vec<Mat4>)>,
    animations: Vec<Animation>,
    parts: Vec<Part>,
    triangles: Vec<[u32; 3]>,
}

struct Ctx<'a> {
    file: &'a str,
    root: &'a Root,
    buffers: Vec<Vec<u8>>,
}

impl Ctx<'_> {
    fn err(&self, entity: impl Into<String>, reason: impl Into<String>) -> TailorError {
        TailorError::parse(self.file, entity, reason)
    }

    /// Reads accessor `index` as `f32`s (integer types converted, normalized ones scaled),
    /// with its element width.
    fn floats(&self, index: usize) -> Result<(Vec<f32>, usize)> {
        let entity = format!("accessor {index}");
        let acc = self.root.accessors.get(index).ok_or_else(|| self.err(&entity, "does not exist"))?;
        if acc.sparse.is_some() {
            return Err(TailorError::Unsupported { file: self.file.into(), entity, reason: "sparse accessor".into() });
        }
        let width = match acc.kind.as_str() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            k => return Err(self.err(&entity, format!("unsupported type {k}"))),
        };
        let size = match acc.component_type {
            5120 | 5121 => 1,
            5122 | 5123 => 2,
            5125 | 5126 => 4,
            c => return Err(self.err(&entity, format!("unknown component type {c}"))),
        };
        if acc.count > MAX_COUNT {
            return Err(self.err(&entity, format!("count {} is implausibly large", acc.count)));
        }
        let Some(view_index) = acc.buffer_view else {
            return Ok((vec![0.0; acc.count * width], width)); // all zeros per the specification
        };
        let view = self.root.buffer_views.get(view_index).ok_or_else(|| self.err(&entity, "missing buffer view"))?;
        let buf = self.buffers.get(view.buffer).ok_or_else(|| self.err(&entity, "missing buffer"))?;
        let elem = width * size;
        let stride = view.byte_stride.unwrap_or(elem).max(elem);
        if !fits(acc.count, stride, elem, acc.byte_offset, view, buf.len()) {
            return Err(self.err(&entity, "reads past the end of its buffer view or buffer"));
        }
        let start = view.byte_offset + acc.byte_offset;
        let mut out = Vec::with_capacity(acc.count * width);
        for i in 0..acc.count {
            for c in 0..width {
                let o = start + i * stride + c * size;
                let b = &buf[o..o + size];
                let n = acc.normalized;
                out.push(match acc.component_type {
                    5120 => (b[0] as i8) as f32 / if n { 127.0 } else { 1.0 },
                    5121 => b[0] as f32 / if n { 255.0 } else { 1.0 },
                    5122 => i16::from_le_bytes([b[0], b[1]]) as f32 / if n { 32767.0 } else { 1.0 },
                    5123 => u16::from_le_bytes([b[0], b[1]]) as f32 / if n { 65535.0 } else { 1.0 },
                    5125 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
                    _ => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                });
            }
        }
        if acc.normalized {
            out.iter_mut().for_each(|v| *v = v.max(-1.0));
        }
        Ok((out, width))
    }

    /// Reads an integer accessor (indices, joints) exactly.
    fn uints(&self, index: usize) -> Result<Vec<u32>> {
        let acc =
            self.root.accessors.get(index).ok_or_else(|| self.err(format!("accessor {index}"), "does not exist"))?;
        if !matches!(acc.component_type, 5121 | 5123 | 5125) || acc.normalized {
            return Err(self.err(format!("accessor {index}"), "expected unsigned integers"));
        }
        if acc.component_type == 5125 {
            // u32 does not round-trip through f32: reread raw.
            let (f, _) = self.floats_raw_u32(index)?;
            return Ok(f);
        }
        Ok(self.floats(index)?.0.into_iter().map(|v| v as u32).collect())
    }

    fn floats_raw_u32(&self, index: usize) -> Result<(Vec<u32>, usize)> {
        let acc = &self.root.accessors[index];
        let width = match acc.kind.as_str() {
            "SCALAR" => 1,
            "VEC4" => 4,
            k => return Err(self.err(format!("accessor {index}"), format!("unsupported type {k} for integers"))),
        };
        let entity = format!("accessor {index}");
        let view = acc
            .buffer_view
            .and_then(|v| self.root.buffer_views.get(v))
            .ok_or_else(|| self.err(&entity, "missing buffer view"))?;
        let buf = self.buffers.get(view.buffer).ok_or_else(|| self.err(&entity, "missing buffer"))?;
        let elem = 4 * width;
        let stride = view.byte_stride.unwrap_or(elem).max(elem);
        if !fits(acc.count, stride, elem, acc.byte_offset, view, buf.len()) {
            return Err(self.err(&entity, "reads past the end of its buffer view or buffer"));
        }
        let start = view.byte_offset + acc.byte_offset;
        let mut out = Vec::with_capacity(acc.count * width);
        for i in 0..acc.count {
            for c in 0..width {
                let o = start + i * stride + 4 * c;
                out.push(u32::from_le_bytes([buf[o], buf[o + 1], buf[o + 2], buf[o + 3]]));
            }
        }
        Ok((out, width))
    }
}

/// Accessors with more elements than this are refused before anything is allocated.
const MAX_COUNT: usize = 1 << 28;

/// Whether `count` elements of `elem` bytes every `stride` bytes, from `offset` in `view`,
/// stay inside the view and the view inside its buffer (computed without overflow).
fn fits(count: usize, stride: usize, elem: usize, offset: usize, view: &BufferView, buf_len: usize) -> bool {
    let need = if count == 0 { 0 } else { (count as u128 - 1) * stride as u128 + elem as u128 };
    offset as u128 + need <= view.byte_length as u128
        && view.byte_offset as u128 + view.byte_length as u128 <= buf_len as u128
}

impl GltfScene {
    /// Loads a `.glb`, or a `.gltf` whose buffers are files next to it.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let bytes = read_bytes(path)?;
        let name = path.display().to_string();
        if bytes.starts_with(b"glTF") {
            Self::from_glb(&bytes, &name)
        } else {
            Self::from_json(&bytes, None, Some(path), &name)
        }
    }

    /// Parses GLB bytes (12-byte header, a JSON chunk, an optional BIN chunk).
    pub fn from_glb(b: &[u8], file: &str) -> Result<Self> {
        let err = |reason: String| TailorError::parse(file, "GLB container", reason);
        let u32_at = |o: usize| b.get(o..o + 4).map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]));
        if !b.starts_with(b"glTF") {
            return Err(err("no glTF magic".into()));
        }
        if u32_at(4) != Some(2) {
            return Err(TailorError::Unsupported {
                file: file.into(),
                entity: "GLB container".into(),
                reason: format!("version {:?} (only glTF 2)", u32_at(4)),
            });
        }
        let mut json = None;
        let mut bin = None;
        let mut o = 12;
        while let (Some(len), Some(kind)) = (u32_at(o), u32_at(o + 4)) {
            let data =
                b.get(o + 8..o + 8 + len as usize).ok_or_else(|| err(format!("chunk at byte {o} is truncated")))?;
            match kind {
                0x4E4F_534A => json = json.or(Some(data)),
                0x004E_4942 => bin = bin.or(Some(data)),
                _ => {}
            }
            o += 8 + len as usize;
        }
        let json = json.ok_or_else(|| err("no JSON chunk".into()))?;
        Self::from_json(json, bin, None, file)
    }

    /// `owner` is the `.gltf` file whose folder holds its external buffers (`None` for a GLB).
    fn from_json(json: &[u8], bin: Option<&[u8]>, owner: Option<&Path>, file: &str) -> Result<Self> {
        let root: Root = serde_json::from_slice(json).map_err(|e| TailorError::parse(file, "JSON", e.to_string()))?;
        let mut buffers = Vec::new();
        for (i, b) in root.buffers.iter().enumerate() {
            let entity = format!("buffer {i}");
            buffers.push(match (&b.uri, bin, owner) {
                (None, Some(bin), _) if i == 0 => bin.to_vec(),
                (Some(uri), _, _) if uri.starts_with("data:") => {
                    return Err(TailorError::Unsupported {
                        file: file.into(),
                        entity,
                        reason: "data: URI buffers".into(),
                    })
                }
                // Confined to the glTF's folder: a URI is data from the file, not a path to trust.
                (Some(uri), _, Some(owner)) => {
                    let bytes = files::read_beside(owner, uri, &entity, files::MAX_INPUT_BYTES)?;
                    if b.byte_length.is_some_and(|n| (bytes.len() as u64) < n) {
                        return Err(TailorError::parse(file, entity, "the buffer file is shorter than its byteLength"));
                    }
                    bytes
                }
                _ => return Err(TailorError::parse(file, entity, "no data (no uri and no GLB binary chunk)")),
            });
        }
        let ctx = Ctx { file, root: &root, buffers };
        let nn = root.nodes.len();

        // Hierarchy: parents, then a parent-before-child order from the scene roots.
        let mut parent = vec![None; nn];
        for (i, n) in root.nodes.iter().enumerate() {
            for &c in &n.children {
                if c >= nn || parent[c].is_some() || c == i {
                    return Err(ctx.err(format!("node {i}"), format!("invalid or shared child {c}")));
                }
                parent[c] = Some(i);
            }
        }
        let roots: Vec<usize> = match root.scene.or(if root.scenes.is_empty() { None } else { Some(0) }) {
            Some(s) => root.scenes.get(s).ok_or_else(|| ctx.err(format!("scene {s}"), "does not exist"))?.nodes.clone(),
            None => (0..nn).filter(|&i| parent[i].is_none()).collect(),
        };
        let mut order = Vec::new();
        let mut seen = vec![false; nn];
        let mut stack: Vec<(usize, Option<usize>)> = roots.iter().rev().map(|&r| (r, None)).collect();
        while let Some((n, p)) = stack.pop() {
            if n >= nn || seen[n] {
                return Err(ctx.err(format!("node {n}"), "missing, or reachable twice (a cycle)"));
            }
            seen[n] = true;
            order.push((n, p));
            stack.extend(root.nodes[n].children.iter().rev().map(|&c| (c, Some(n))));
        }
        let mut rest = Vec::with_capacity(nn);
        for (i, n) in root.nodes.iter().enumerate() {
            let finite = |v: &[f32]| v.iter().all(|c| c.is_finite());
            let all = [
                n.translation.as_ref().map(|v| &v[..]),
                n.scale.as_ref().map(|v| &v[..]),
                n.matrix.as_ref().map(|v| &v[..]),
            ];
            if !all.iter().flatten().all(|v| finite(v)) {
                return Err(ctx.err(format!("node {i}"), "non-finite translation, scale or matrix"));
            }
            let r = match n.rotation {
                Some(q) => unit_quat(q).ok_or_else(|| {
                    ctx.err(format!("node {i}"), format!("rotation {q:?} is not a finite, non-zero quaternion"))
                })?,
                None => Quat::IDENTITY,
            };
            rest.push(Trs {
                t: n.translation.map(Vec3::from).unwrap_or(Vec3::ZERO),
                r,
                s: n.scale.map(Vec3::from).unwrap_or(Vec3::ONE),
            });
        }
        let matrices = root.nodes.iter().map(|n| n.matrix.map(|m| Mat4::from_cols_array(&m))).collect();

        let mut skins = Vec::new();
        for (s, skin) in root.skins.iter().enumerate() {
            if let Some(&j) = skin.joints.iter().find(|&&j| j >= nn) {
                return Err(ctx.err(format!("skin {s}"), format!("joint node {j} does not exist")));
            }
            let ibm = match skin.inverse_bind_matrices {
                Some(a) => {
                    let (f, w) = ctx.floats(a)?;
                    if w != 16 || f.len() / 16 < skin.joints.len() {
                        return Err(ctx.err(format!("skin {s}"), "inverse bind matrices are not one MAT4 per joint"));
                    }
                    f.chunks_exact(16).map(Mat4::from_cols_slice).collect()
                }
                None => vec![Mat4::IDENTITY; skin.joints.len()],
            };
            skins.push((skin.joints.clone(), ibm));
        }

        let mut animations = Vec::new();
        for (a, anim) in root.animations.iter().enumerate() {
            let mut channels = Vec::new();
            let mut duration = 0.0f32;
            for (c, ch) in anim.channels.iter().enumerate() {
                let entity = format!("animation {a} channel {c}");
                let path = match ch.target.path.as_str() {
                    "translation" => Path3::Translation,
                    "rotation" => Path3::Rotation,
                    "scale" => Path3::Scale,
                    _ => continue, // morph weights
                };
                let Some(node) = ch.target.node.filter(|&n| n < nn) else { continue };
                let sampler = anim.samplers.get(ch.sampler).ok_or_else(|| ctx.err(&entity, "missing sampler"))?;
                let interp = match sampler.interpolation.as_deref().unwrap_or("LINEAR") {
                    "LINEAR" => Interp::Linear,
                    "STEP" => Interp::Step,
                    "CUBICSPLINE" => Interp::Cubic,
                    i => return Err(ctx.err(&entity, format!("unknown interpolation {i}"))),
                };
                let (times, _) = ctx.floats(sampler.input)?;
                let (values, width) = ctx.floats(sampler.output)?;
                let want = if path == Path3::Rotation { 4 } else { 3 };
                let per_key = if interp == Interp::Cubic { 3 } else { 1 };
                if times.is_empty() || width != want || values.len() != times.len() * want * per_key {
                    return Err(ctx.err(&entity, "sampler input and output do not match"));
                }
                if times.windows(2).any(|w| w[1].partial_cmp(&w[0]).is_none_or(|o| o.is_lt())) {
                    return Err(ctx.err(&entity, "key times are not increasing"));
                }
                if times.iter().chain(&values).any(|v| !v.is_finite()) {
                    return Err(ctx.err(&entity, "non-finite key time or value"));
                }
                if path == Path3::Rotation
                    && values.chunks_exact(4).any(|q| unit_quat([q[0], q[1], q[2], q[3]]).is_none())
                    && interp != Interp::Cubic
                {
                    return Err(ctx.err(&entity, "a rotation key is not a non-zero quaternion"));
                }
                duration = duration.max(*times.last().unwrap_or(&0.0));
                channels.push(Channel { node, path, interp, times, values });
            }
            animations.push(Animation {
                name: anim.name.clone().unwrap_or_else(|| format!("animation {a}")),
                duration,
                channels,
            });
        }

        let mut parts = Vec::new();
        let mut triangles = Vec::new();
        let mut base = 0u32;
        for &(n, _) in &order {
            let node = &root.nodes[n];
            let Some(m) = node.mesh else { continue };
            let mesh =
                root.meshes.get(m).ok_or_else(|| ctx.err(format!("node {n}"), format!("mesh {m} does not exist")))?;
            let skin = node.skin.filter(|&s| s < skins.len());
            for (p, prim) in mesh.primitives.iter().enumerate() {
                let entity = format!("mesh {m} primitive {p}");
                let mode = prim.mode.unwrap_or(4);
                if mode < 4 {
                    continue;
                }
                let &pos = prim.attributes.get("POSITION").ok_or_else(|| ctx.err(&entity, "no POSITION"))?;
                let (pf, w) = ctx.floats(pos)?;
                if w != 3 {
                    return Err(ctx.err(&entity, "POSITION is not VEC3"));
                }
                let positions: Vec<Vec3> = pf.chunks_exact(3).map(Vec3::from_slice).collect();
                let nv = positions.len();
                let idx = match prim.indices {
                    Some(i) => ctx.uints(i)?,
                    None => (0..nv as u32).collect(),
                };
                if let Some(&bad) = idx.iter().find(|&&i| i as usize >= nv) {
                    return Err(ctx.err(&entity, format!("index {bad} is out of range ({nv} vertices)")));
                }
                let tris: Vec<[u32; 3]> = match mode {
                    4 => idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
                    5 => (0..idx.len().saturating_sub(2))
                        .map(|i| {
                            if i % 2 == 0 {
                                [idx[i], idx[i + 1], idx[i + 2]]
                            } else {
                                [idx[i + 1], idx[i], idx[i + 2]]
                            }
                        })
                        .collect(),
                    6 => (1..idx.len().saturating_sub(1)).map(|i| [idx[0], idx[i], idx[i + 1]]).collect(),
                    _ => return Err(ctx.err(&entity, format!("unknown primitive mode {mode}"))),
                };
                let (joints, weights) = match (skin, prim.attributes.get("JOINTS_0"), prim.attributes.get("WEIGHTS_0"))
                {
                    (Some(s), Some(&j), Some(&wt)) => {
                        let j = ctx.uints(j)?;
                        let (wf, ww) = ctx.floats(wt)?;
                        if j.len() != 4 * nv || ww != 4 || wf.len() != 4 * nv {
                            return Err(ctx.err(&entity, "JOINTS_0/WEIGHTS_0 are not one VEC4 per vertex"));
                        }
                        let nj = skins[s].0.len() as u32;
                        if let Some(&bad) = j.iter().find(|&&x| x >= nj) {
                            return Err(ctx.err(&entity, format!("joint {bad} is out of range ({nj} joints)")));
                        }
                        (
                            j.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect(),
                            wf.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect(),
                        )
                    }
                    _ => (Vec::new(), Vec::new()),
                };
                let skin = if joints.is_empty() { None } else { skin };
                triangles.extend(tris.iter().map(|t| t.map(|i| i + base)));
                base += nv as u32;
                parts.push(Part { node: n, skin, positions, joints, weights });
            }
        }
        if parts.is_empty() {
            return Err(TailorError::EmptyMesh { what: format!("{file}: no triangle mesh in the scene") });
        }
        let scene = Self { file: file.into(), order, rest, matrices, skins, animations, parts, triangles };
        // Finite inputs can still overflow once chained (huge scales, matrices): the rest pose
        // must come out finite, or the file is refused here rather than simulated as NaN.
        scene.mesh_at(None, 0.0)?.validate(file)?;
        Ok(scene)
    }

    /// Total vertex count over all primitives.
    pub fn num_vertices(&self) -> usize {
        self.parts.iter().map(|p| p.positions.len()).sum()
    }

    /// The triangles (constant over time).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The animations in file order.
    pub fn animations(&self) -> &[Animation] {
        &self.animations
    }

    /// World-space vertex positions at `time` (seconds) of `animation` (`None`: the rest
    /// pose), written into `out` (its allocation is reused).
    pub fn positions_at(&self, animation: Option<usize>, time: f32, out: &mut Vec<[f32; 3]>) -> Result<()> {
        if !time.is_finite() {
            return Err(TailorError::setting("time", time, "must be a finite number of seconds"));
        }
        let mut local = self.rest.clone();
        if let Some(a) = animation {
            let anim = self.animations.get(a).ok_or_else(|| {
                TailorError::parse(
                    &self.file,
                    format!("animation {a}"),
                    format!("only {} animations", self.animations.len()),
                )
            })?;
            for ch in &anim.channels {
                let v = sample(ch, time);
                let trs = &mut local[ch.node];
                match ch.path {
                    Path3::Translation => trs.t = v.truncate(),
                    Path3::Scale => trs.s = v.truncate(),
                    // A slerp or spline between valid keys can still pass through zero.
                    Path3::Rotation => trs.r = unit_quat(v.to_array()).unwrap_or(trs.r),
                }
            }
        }
        let mut global = vec![Mat4::IDENTITY; self.rest.len()];
        for &(n, p) in &self.order {
            let l = match self.matrices[n] {
                Some(m) => m,
                None => Mat4::from_scale_rotation_translation(local[n].s, local[n].r, local[n].t),
            };
            global[n] = p.map_or(l, |p| global[p] * l);
        }
        out.clear();
        let mut joint_mats = Vec::new();
        for part in &self.parts {
            match part.skin {
                Some(s) => {
                    let (joints, ibm) = &self.skins[s];
                    joint_mats.clear();
                    joint_mats.extend(joints.iter().zip(ibm).map(|(&j, m)| global[j] * *m));
                    for ((v, j), w) in part.positions.iter().zip(&part.joints).zip(&part.weights) {
                        let v4 = Vec4::from((*v, 1.0));
                        let mut acc = Vec4::ZERO;
                        for k in 0..4 {
                            if w[k] != 0.0 {
                                acc += w[k] * (joint_mats[j[k] as usize] * v4);
                            }
                        }
                        let wsum = w.iter().sum::<f32>();
                        let p = if wsum > 0.0 { acc.truncate() / wsum } else { *v };
                        out.push(p.into());
                    }
                }
                None => {
                    let g = global[part.node];
                    out.extend(part.positions.iter().map(|v| <[f32; 3]>::from(g.transform_point3(*v))));
                }
            }
        }
        Ok(())
    }

    /// The mesh at `time` of `animation` (`None`: rest pose).
    pub fn mesh_at(&self, animation: Option<usize>, time: f32) -> Result<TriMesh> {
        let mut positions = Vec::new();
        self.positions_at(animation, time, &mut positions)?;
        Ok(TriMesh { positions, triangles: self.triangles.clone() })
    }
}

/// `q` as a unit quaternion, `None` unless it is finite and non-zero. The norm is taken in
/// f64: a component of 1.8e19 squares past f32's range, and glam's `normalize` then gives NaN.
fn unit_quat(q: [f32; 4]) -> Option<Quat> {
    let n = q.iter().map(|&c| (c as f64) * (c as f64)).sum::<f64>().sqrt();
    if !(n.is_finite() && n > 0.0) {
        return None;
    }
    Some(Quat::from_xyzw(
        (q[0] as f64 / n) as f32,
        (q[1] as f64 / n) as f32,
        (q[2] as f64 / n) as f32,
        (q[3] as f64 / n) as f32,
    ))
}

/// Samples a channel at time `t` (clamped to the key range) as a `Vec4`.
fn sample(ch: &Channel, t: f32) -> Vec4 {
    let w = if ch.path == Path3::Rotation { 4 } else { 3 };
    let stride = if ch.interp == Interp::Cubic { 3 * w } else { w };
    // Value of key `k`; for cubic splines the value sits between the in- and out-tangents.
    let at = |k: usize, part: usize| {
        let o = k * stride + part * w;
        let v = &ch.values[o..o + w];
        if w == 4 {
            Vec4::from_slice(v)
        } else {
            Vec4::new(v[0], v[1], v[2], 0.0)
        }
    };
    let value_part = if ch.interp == Interp::Cubic { 1 } else { 0 };
    let n = ch.times.len();
    if t <= ch.times[0] || n == 1 {
        return at(0, value_part);
    }
    if t >= ch.times[n - 1] {
        return at(n - 1, value_part);
    }
    let k = ch.times.partition_point(|&x| x <= t) - 1;
    let (t0, t1) = (ch.times[k], ch.times[k + 1]);
    let dt = t1 - t0;
    let s = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
    match ch.interp {
        Interp::Step => at(k, 0),
        Interp::Linear if w == 4 => {
            let (a, mut b) = (Quat::from_vec4(at(k, 0)), Quat::from_vec4(at(k + 1, 0)));
            if a.dot(b) < 0.0 {
                b = -b; // shortest arc
            }
            Vec4::from(a.slerp(b, s))
        }
        Interp::Linear => at(k, 0).lerp(at(k + 1, 0), s),
        Interp::Cubic => {
            let (s2, s3) = (s * s, s * s * s);
            let v0 = at(k, 1);
            let b0 = at(k, 2);
            let a1 = at(k + 1, 0);
            let v1 = at(k + 1, 1);
            v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                + b0 * (dt * (s3 - 2.0 * s2 + s))
                + v1 * (-2.0 * s3 + 3.0 * s2)
                + a1 * (dt * (s3 - s2))
        }
    }
}

#[cfg(test)]
mod tests;
