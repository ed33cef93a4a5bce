//! Scene geometry: the models of a scene loaded, their instances baked into
//! world-space base patches, and the shading normals beside them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DMat4;

use super::bpt;
use super::desc::{ModelDesc, Scene, Surface};
use super::displacement::{ModelDisplacement, SceneDisplacement};
use super::instances::{Instance, InstanceTable};
use super::material::{eval_uv_patch, parametric_uv_patch, SceneMaterials};
use super::pn::{self, PnMesh, PnScene};
use crate::cage::model::ImportedModel;
use crate::cage::obj;
use crate::cage::obj::CageOptions;
use crate::constants::{PATCH_MODEL_SHIFT, PATCH_RATIONAL};
use crate::figures::{bytes_text, thousands};
use crate::input::limits::{GEOMETRY_BYTES_PER_PATCH, MAX_BASE_PATCHES, MAX_COORD};
use crate::input::SceneError;
use crate::patch::bezier::BezierPatch;
use crate::patch::oracle::PATCH_TWO_SIDED;
use crate::patch::rational::{is_polynomial, Weights, UNIT_WEIGHTS};
use crate::patch::shading::{ShadingPatch, SHADING_BYTES_PER_PATCH};

/// What a model contributed to the scene geometry.
#[derive(Clone, Debug)]
pub struct ModelSummary {
    /// Display name.
    pub name: String,
    /// Model file.
    pub file: PathBuf,
    /// Base patches in one instance.
    pub patches_per_instance: usize,
    /// Number of instances.
    pub instances: usize,
    /// Never back-face culled.
    pub two_sided: bool,
    /// Import warnings.
    pub warnings: Vec<String>,
}

/// World-space base patches of a whole scene.
#[derive(Clone, Debug, Default)]
pub struct SceneGeometry {
    /// Base patches of every instance of every model, in scene order.
    pub patches: Vec<BezierPatch>,
    /// Per patch: `PATCH_TWO_SIDED`, `PATCH_RATIONAL` and the model index
    /// `<< PATCH_MODEL_SHIFT`.
    pub flags: Vec<u32>,
    /// Per model, in scene order.
    pub models: Vec<ModelSummary>,
    /// The weights of every patch, parallel to `patches`, when some patch is
    /// rational (has a weight other than 1); empty otherwise, which is how
    /// every polynomial scene stays exactly what it was.
    pub weights: Vec<Weights>,
    /// The PN-triangle models' triangles in world space (`surface =
    /// "pn-triangles"`), beside the patches; empty for most scenes.
    pub pn: PnScene,
    /// What the GPU holds instead of `patches`: each model's patches once
    /// and the instances that place them, which make exactly `patches`
    /// (empty for a geometry made by hand: the GPU then reads `patches` as
    /// they are).
    pub instances: InstanceTable,
    /// UV patches parallel to `instances.patches` and the models' albedo
    /// maps (empty for a geometry made by hand).
    pub materials: SceneMaterials,
    /// The displaced models' maps and the owner records (empty when no
    /// model is displaced).
    pub displacement: SceneDisplacement,
}

impl SceneGeometry {
    /// Patches with a weight other than 1.
    pub fn rational_patches(&self) -> usize {
        self.weights.iter().filter(|w| !is_polynomial(w)).count()
    }

    /// Whether some patch is rational.
    pub fn is_rational(&self) -> bool {
        self.rational_patches() > 0
    }

    /// The weights of patch `k` (all 1 for a polynomial scene).
    pub fn weights_of(&self, k: usize) -> Weights {
        self.weights.get(k).copied().unwrap_or(UNIT_WEIGHTS)
    }

    /// The texture coordinates at base patch `patch`'s (u, v): its model
    /// patch's UV patch there, at (v, u) for a mirrored instance (the
    /// twin of `surface_uv` in `glsl/common/texture.glsl`); (u, v) itself
    /// for a geometry without UV patches.
    pub fn surface_uv(&self, patch: usize, u: f32, v: f32) -> [f32; 2] {
        if self.materials.uv_patches.len() != self.instances.patches.len()
            || self.instances.instances.is_empty()
        {
            return [u, v];
        }
        let (t, k) = self.instances.locate(patch);
        let (u, v) = if t.mirrored() { (v, u) } else { (u, v) };
        eval_uv_patch(&self.materials.uv_patches[k], u, v)
    }

    /// The patches `range` of this geometry with their flags, weights and
    /// the one model summary `model` (a model's instance, for the hole test).
    /// The patches' model index becomes 0, the subset's one model; when
    /// scene model `index` is displaced, the subset is too: its map, its UV
    /// patches (transposed for a mirrored instance, as its world patches
    /// are) and owner records made again over the subset's own patches.
    pub fn subset(
        &self,
        range: std::ops::Range<usize>,
        (index, model): (usize, ModelSummary),
    ) -> SceneGeometry {
        let weights = if self.weights.is_empty() {
            Vec::new()
        } else {
            self.weights[range.clone()].to_vec()
        };
        let model_bits = u32::MAX << PATCH_MODEL_SHIFT;
        let mut geo = SceneGeometry {
            patches: self.patches[range.clone()].to_vec(),
            flags: self.flags[range.clone()]
                .iter()
                .map(|f| f & !model_bits)
                .collect(),
            models: vec![model],
            weights,
            pn: PnScene::default(),
            instances: InstanceTable::default(),
            materials: SceneMaterials::default(),
            displacement: SceneDisplacement::default(),
        };
        if !geo.is_rational() {
            geo.weights.clear();
        }
        if let Some(Some(d)) = self.displacement.models.get(index) {
            self.displace_subset(&mut geo, range, d);
        }
        geo
    }

    /// Gives `sub` (the patches `range`, see [`SceneGeometry::subset`])
    /// this geometry's displacement `d` of their model.
    fn displace_subset(
        &self,
        sub: &mut SceneGeometry,
        range: std::ops::Range<usize>,
        d: &ModelDisplacement,
    ) {
        let uv_patches = range
            .map(|g| {
                let (t, k) = self.instances.locate(g);
                let uv = self.materials.uv_patches[k];
                if t.mirrored() {
                    std::array::from_fn(|i| uv[(i % 4) * 4 + i / 4])
                } else {
                    uv
                }
            })
            .collect::<Vec<_>>();
        sub.instances = InstanceTable::identity(&sub.patches, &sub.flags, &sub.weights);
        sub.materials = SceneMaterials {
            model_texture: vec![None],
            uv_patches,
            ..SceneMaterials::default()
        };
        sub.displacement = SceneDisplacement {
            maps: vec![self.displacement.maps[d.map].clone()],
            models: vec![Some(ModelDisplacement { map: 0, ..*d })],
            ..SceneDisplacement::default()
        };
        sub.displacement
            .finish(&sub.instances, &sub.materials.uv_patches);
    }
}

/// Shading normals of a whole scene, beside its [`SceneGeometry`]: one
/// [`ShadingPatch`] per base patch, in the same order (see `shading.rs` for
/// the layout a GPU buffer takes).
#[derive(Clone, Debug, Default)]
pub struct SceneShading {
    /// Tangent patches in world space, parallel to `SceneGeometry::patches`
    /// (what the host's checks and previews read).
    pub patches: Vec<ShadingPatch>,
    /// Tangent patches in model space, parallel to the model patches of
    /// `SceneGeometry::instances` (what the GPU reads; the fragment shader
    /// transforms them by the instance). Empty: the GPU reads `patches`.
    pub model: Vec<ShadingPatch>,
}

impl SceneShading {
    /// Shading with the patches' own derivatives (what a scene without
    /// tangent patches, or a caller that does not need smooth normals,
    /// draws with).
    pub fn from_geometry(patches: &[BezierPatch]) -> Self {
        SceneShading {
            patches: patches.iter().map(ShadingPatch::from_geometry).collect(),
            model: Vec::new(),
        }
    }

    /// Shading with the patches' own derivatives for a whole geometry: the
    /// world patches' and, for the GPU, its model patches' (so a geometry
    /// with instances is uploaded as such).
    pub fn own_derivatives(geo: &SceneGeometry) -> Self {
        SceneShading {
            model: Self::from_geometry(&geo.instances.patches).patches,
            ..Self::from_geometry(&geo.patches)
        }
    }

    /// Unnormalised shading normal of base patch `patch` at (u, v).
    pub fn normal(&self, patch: usize, u: f32, v: f32) -> glam::Vec3 {
        self.patches[patch].normal(u, v)
    }

    /// Bytes of the tightly packed GPU buffer.
    pub fn bytes(&self) -> usize {
        self.patches.len() * SHADING_BYTES_PER_PATCH
    }

    /// The buffer's contents: 72 f32 per base patch.
    pub fn to_floats(&self) -> Vec<f32> {
        self.patches.iter().flat_map(|p| p.to_floats()).collect()
    }
}

/// What names one import: the model file, its cage options and surface.
pub(crate) type ModelKey = (PathBuf, CageOptions, Surface);

/// Imported models by file, cage options and surface.
pub(crate) type ModelCache = HashMap<ModelKey, ImportedModel>;

/// Loads one model file by extension (`.bpt` or `.obj`).
pub fn load_model(path: &Path) -> Result<ImportedModel, SceneError> {
    load_model_with(path, &CageOptions::default())
}

/// [`load_model`] with choices for cages (ignored, with a warning, for
/// `.bpt` files).
pub fn load_model_with(path: &Path, options: &CageOptions) -> Result<ImportedModel, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let patch_file_warnings = || -> Vec<String> {
        let mut w: Vec<String> = options
            .boundary
            .map(|r| format!("boundary rule {r} ignored: a patch file holds patches, not a cage"))
            .into_iter()
            .collect();
        if options.isolate > 0 {
            w.push(format!(
                "isolate {} ignored: a patch file holds patches, not a cage",
                options.isolate
            ));
        }
        w
    };
    match ext.as_deref() {
        Some("bpt") => Ok(ImportedModel {
            patches: bpt::read(path)?,
            warnings: patch_file_warnings(),
            ..Default::default()
        }),
        Some("rbpt") => {
            let (patches, weights) = bpt::read_rational(path)?;
            Ok(ImportedModel {
                patches,
                weights,
                warnings: patch_file_warnings(),
                ..Default::default()
            })
        }
        Some("obj") => obj::read_with(path, options),
        _ => Err(SceneError::Invalid {
            path: path.to_path_buf(),
            msg: "unknown model format: expected a .bpt patch file, a .rbpt rational patch file or a .obj Catmull-Clark cage"
                .into(),
        }),
    }
}

impl Scene {
    /// Loads every model file (each once) and bakes the instances into
    /// world-space base patches.
    pub fn geometry(&self) -> Result<SceneGeometry, SceneError> {
        self.build(false).map(|(geo, _)| geo)
    }

    /// [`Scene::geometry`] and the shading normals beside it.
    pub fn geometry_and_shading(&self) -> Result<(SceneGeometry, SceneShading), SceneError> {
        self.build(true)
    }

    fn build(&self, with_shading: bool) -> Result<(SceneGeometry, SceneShading), SceneError> {
        self.build_with_models(with_shading).map(|(g, s, _)| (g, s))
    }

    /// [`Scene::geometry_and_shading`] and the imported models (for
    /// animation), by model file, options and surface.
    pub(crate) fn build_with_models(
        &self,
        with_shading: bool,
    ) -> Result<(SceneGeometry, SceneShading, ModelCache), SceneError> {
        let (cache, meshes) = self.load_models()?;
        // Refuse what cannot be drawn before allocating any of it.
        self.check_base_patches(&cache)?;
        let rational = self.models.iter().any(|m| {
            let model = &cache[&(m.file.clone(), m.options, m.surface)];
            !m.instances.is_empty() && model.weights.iter().any(|w| !is_polynomial(w))
        });
        let mut builder = Builder {
            scene: self,
            cache: &cache,
            meshes: &meshes,
            with_shading,
            rational,
            sources: HashMap::new(),
            geo: SceneGeometry::default(),
            shading: SceneShading::default(),
        };
        for (index, m) in self.models.iter().enumerate() {
            builder.add_model(index, m)?;
        }
        let Builder {
            mut geo, shading, ..
        } = builder;
        self.check_pn_triangles(&geo)?;
        geo.pn.number_edges();
        let SceneGeometry {
            instances,
            materials,
            displacement,
            ..
        } = &mut geo;
        displacement.finish(instances, &materials.uv_patches);
        Ok((geo, shading, cache))
    }

    /// The error for model `m` of this scene.
    fn model_error(&self, m: &ModelDesc, msg: String) -> SceneError {
        SceneError::Model {
            scene: self.path.clone(),
            model: m.name.clone(),
            msg,
        }
    }

    /// Reads every PN-triangle mesh (each file once), then imports every
    /// other model (each file, options and surface once), in scene order.
    fn load_models(&self) -> Result<(ModelCache, HashMap<PathBuf, PnMesh>), SceneError> {
        let mut cache: HashMap<(PathBuf, CageOptions, Surface), ImportedModel> = HashMap::new();
        let mut meshes: HashMap<PathBuf, PnMesh> = HashMap::new();
        for m in self
            .models
            .iter()
            .filter(|m| m.surface == Surface::PnTriangles)
        {
            if !meshes.contains_key(&m.file) {
                let mesh = pn::read(&m.file).map_err(|e| self.model_error(m, e.to_string()))?;
                meshes.insert(m.file.clone(), mesh);
            }
        }
        // PN-triangle models hold no patches: they stand as empty imports.
        for m in self
            .models
            .iter()
            .filter(|m| m.surface == Surface::PnTriangles)
        {
            cache.insert(
                (m.file.clone(), m.options, m.surface),
                ImportedModel::default(),
            );
        }
        for m in &self.models {
            let key = (m.file.clone(), m.options, m.surface);
            if let std::collections::hash_map::Entry::Vacant(slot) = cache.entry(key) {
                let model = load_model_with(&m.file, &m.options)
                    .map_err(|e| self.model_error(m, e.to_string()))?;
                slot.insert(model);
            }
        }
        Ok((cache, meshes))
    }

    /// Refuses a scene with more base patches than the subdivision kernel
    /// can count.
    fn check_base_patches(&self, cache: &ModelCache) -> Result<(), SceneError> {
        let total: u64 = self
            .models
            .iter()
            .map(|m| {
                cache[&(m.file.clone(), m.options, m.surface)].patches.len() as u64
                    * m.instances.len() as u64
            })
            .fold(0, u64::saturating_add);
        if total > MAX_BASE_PATCHES {
            return Err(SceneError::invalid(
                &self.path,
                format!(
                    "the scene has {} base patches ({} for their control points and flags); \
                     at most {} can be subdivided",
                    thousands(total),
                    bytes_text(total.saturating_mul(GEOMETRY_BYTES_PER_PATCH)),
                    thousands(MAX_BASE_PATCHES)
                ),
            ));
        }
        Ok(())
    }

    /// Refuses a scene with more PN triangles than cudatess can number.
    fn check_pn_triangles(&self, geo: &SceneGeometry) -> Result<(), SceneError> {
        // cudatess's vertex word holds the triangle id in CT_PATCH_BITS.
        let most = 1u64 << crate::constants::CT_PATCH_BITS;
        if u64::from(geo.pn.count()) > most {
            return Err(SceneError::invalid(
                &self.path,
                format!(
                    "the scene has {} PN triangles; at most {} can be drawn",
                    thousands(u64::from(geo.pn.count())),
                    thousands(most)
                ),
            ));
        }
        Ok(())
    }
}

/// A scene's geometry and shading as they are built, model by model, with
/// the loaded models they are built from.
struct Builder<'a> {
    /// The scene (for its path in errors).
    scene: &'a Scene,
    /// Imported models by file, cage options and surface.
    cache: &'a ModelCache,
    /// PN-triangle meshes by file.
    meshes: &'a HashMap<PathBuf, PnMesh>,
    /// Whether to build the shading normals too.
    with_shading: bool,
    /// Whether some placed patch is rational (then every patch keeps weights).
    rational: bool,
    /// Where each distinct import's model patches start in
    /// `geo.instances.patches` (a deforming model: its own copy).
    sources: HashMap<(ModelKey, Option<usize>), u32>,
    /// The geometry so far.
    geo: SceneGeometry,
    /// The shading so far.
    shading: SceneShading,
}

impl Builder<'_> {
    /// Adds model `index` of the scene: its patches once in model space, its
    /// instances' patches in world space, its PN triangles and its summary.
    fn add_model(&mut self, index: usize, m: &ModelDesc) -> Result<(), SceneError> {
        let key = (m.file.clone(), m.options, m.surface);
        let model = &self.cache[&key];
        let flags =
            (index as u32) << PATCH_MODEL_SHIFT | if m.two_sided { PATCH_TWO_SIDED } else { 0 };
        let placed = !m.instances.is_empty() && !model.patches.is_empty();
        let tangents = if self.with_shading && placed {
            model.shading_patches()
        } else {
            Vec::new()
        };
        // Each distinct import's patches once, in model space: where its
        // first model with instances puts them.
        // A model whose cage moves (src/anim/) has a copy of its own, which
        // the animation rewrites every frame.
        let source_key = (key.clone(), m.anim.deforms().then_some(index));
        if placed && !self.sources.contains_key(&source_key) {
            self.sources
                .insert(source_key.clone(), self.geo.instances.patches.len() as u32);
            add_model_patches(&mut self.geo.instances, model, self.rational);
            self.shading.model.extend_from_slice(&tangents);
            add_uv_patches(&mut self.geo.materials, model);
        }
        if placed {
            let source = self.sources[&source_key];
            self.place_instances(m, model, source, flags, &tangents)?;
        }
        self.place_pn(m, flags)?;
        let texture = match m
            .texture
            .as_ref()
            .or(model.albedo.as_ref().map(|a| &a.path))
        {
            Some(path) if m.surface != Surface::PnTriangles => Some(
                self.geo
                    .materials
                    .texture_index(path)
                    .map_err(|e| self.scene.model_error(m, e.to_string()))?,
            ),
            _ => None,
        };
        self.geo.materials.model_texture.push(texture);
        let displacement = match &m.displacement {
            Some(d) => {
                if model.weights.iter().any(|w| !is_polynomial(w)) {
                    return Err(self.scene.model_error(
                        m,
                        "displacement needs polynomial patches; this model has weights".into(),
                    ));
                }
                let map = self
                    .geo
                    .displacement
                    .map_index(&d.map)
                    .map_err(|e| self.scene.model_error(m, e.to_string()))?;
                Some(ModelDisplacement {
                    map,
                    scale: d.scale,
                    bias: d.bias,
                })
            }
            None => None,
        };
        self.geo.displacement.models.push(displacement);
        self.geo.models.push(ModelSummary {
            name: m.name.clone(),
            file: m.file.clone(),
            patches_per_instance: model.patches.len(),
            instances: m.instances.len(),
            two_sided: m.two_sided,
            warnings: model
                .warnings
                .iter()
                .cloned()
                .chain(
                    (m.texture.is_some() && m.surface == Surface::PnTriangles).then(|| {
                        "texture ignored: PN triangles carry no texture coordinates".to_string()
                    }),
                )
                .collect(),
        });
        Ok(())
    }

    /// Places every instance of `m`: its world-space patches, flags, weights
    /// and shading, and the instance that makes them from the model patches
    /// at `source`.
    fn place_instances(
        &mut self,
        m: &ModelDesc,
        model: &ImportedModel,
        source: u32,
        flags: u32,
        tangents: &[ShadingPatch],
    ) -> Result<(), SceneError> {
        let geo = &mut self.geo;
        for xf in &m.instances {
            let first = geo.patches.len() as u32;
            let instance = Instance::new(xf, first, source, model.patches.len() as u32, flags);
            for k in 0..model.patches.len() {
                let source = instance.source as usize + k;
                let w = instance.patch(&geo.instances.patches[source]);
                if !w.pts.iter().all(|q| q.abs().max_element() <= MAX_COORD) {
                    return Err(self.scene.model_error(
                        m,
                        format!("a transformed control point exceeds ±{MAX_COORD} (scale the scene down)"),
                    ));
                }
                geo.patches.push(w);
                geo.flags
                    .push(instance.patch_flags(geo.instances.flags[source]));
                if self.rational {
                    geo.weights
                        .push(instance.weights(&geo.instances.weights[source]));
                }
                if let Some(t) = tangents.get(k) {
                    self.shading.patches.push(t.transformed(xf));
                }
            }
            let world = &geo.patches[first as usize..];
            let mut record = instance.bounded(world);
            // A displaced surface reaches beyond its control points.
            if let Some(d) = &m.displacement {
                let g = d.margin();
                for k in 0..3 {
                    record.lo[k] -= g;
                    record.hi[k] += g;
                }
            }
            geo.instances.instances.push(record);
        }
        Ok(())
    }

    /// Places every instance of a PN-triangle model `m`'s mesh in world
    /// space (nothing for a patch model).
    fn place_pn(&mut self, m: &ModelDesc, flags: u32) -> Result<(), SceneError> {
        let Some(mesh) = self
            .meshes
            .get(&m.file)
            .filter(|_| m.surface == Surface::PnTriangles)
        else {
            return Ok(());
        };
        for xf in &m.instances {
            let w = mesh.transformed(xf);
            if !w
                .positions
                .iter()
                .all(|q| q.abs().max_element() <= MAX_COORD)
            {
                return Err(self.scene.model_error(
                    m,
                    format!("a transformed vertex exceeds ±{MAX_COORD} (scale the scene down)"),
                ));
            }
            self.geo.pn.push(&w, flags);
        }
        Ok(())
    }
}

/// Appends `model`'s patches to the model patches of `table` (canonical
/// zeros: an identity instance reads them unchanged), with their flags and
/// their weights (when the scene has rational patches).
fn add_model_patches(table: &mut InstanceTable, model: &ImportedModel, rational: bool) {
    for (k, p) in model.patches.iter().enumerate() {
        table.patches.push(p.canonical_zeros());
        let weights = model.weights.get(k).copied().unwrap_or(UNIT_WEIGHTS);
        let flag = if is_polynomial(&weights) {
            0
        } else {
            PATCH_RATIONAL
        };
        table.flags.push(flag);
        if rational {
            table.weights.push(weights);
        }
    }
}

/// Appends `model`'s UV patches to `materials`, parallel to its model
/// patches: the cage's where it has texture coordinates, else parametric.
fn add_uv_patches(materials: &mut SceneMaterials, model: &ImportedModel) {
    match &model.uv_patches {
        Some(uv) if uv.patches.len() == model.patches.len() => {
            materials.uv_patches.extend_from_slice(&uv.patches);
            materials.cage_uv_patches += uv.patches.len();
        }
        _ => materials.uv_patches.extend(std::iter::repeat_n(
            parametric_uv_patch(),
            model.patches.len(),
        )),
    }
}

/// Applies an affine transform to a patch's control points, as an
/// instance does (`Instance::patch`: the f32 transform the GPU applies;
/// mirroring transforms swap u and v so ∂u × ∂v stays outward).
pub fn transform_patch(p: &BezierPatch, m: &DMat4) -> BezierPatch {
    Instance::new(m, 0, 0, 1, 0).patch(&p.canonical_zeros())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn mirroring_keeps_normals_outward() {
        let mut pts = [glam::Vec3::ZERO; 16];
        for j in 0..4 {
            for i in 0..4 {
                pts[4 * j + i] = glam::Vec3::new(i as f32, j as f32, 0.0);
            }
        }
        let p = BezierPatch { pts };
        let n0 = p.normal(0.5, 0.5);
        let m = DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0)) * DMat4::from_rotation_x(0.3);
        let q = transform_patch(&p, &m);
        let want = m.transform_vector3(n0.as_dvec3());
        // The mirrored normal of the original surface, as an oriented plane,
        // should agree with the new patch's normal after the u/v swap.
        let got = q.normal(0.5, 0.5).as_dvec3();
        assert!(got.dot(want) > 0.0);
    }

    #[test]
    fn transforms_follow_the_geometry() {
        let p = crate::patch::fixtures::wavy();
        let s = ShadingPatch::from_geometry(&p);
        for m in [
            DMat4::from_rotation_z(0.4) * DMat4::from_scale(DVec3::new(2.0, 1.0, 0.5)),
            DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)) * DMat4::from_rotation_x(0.3),
        ] {
            let moved = transform_patch(&p, &m);
            let want = ShadingPatch::from_geometry(&moved);
            let got = s.transformed(&m);
            for (a, b) in got
                .du
                .iter()
                .chain(&got.dv)
                .zip(want.du.iter().chain(&want.dv))
            {
                assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
            }
        }
    }
}
