//! What every sample of a render reads: the scene, its BVH, its lights, the
//! settings they were built for, the camera's rays and the continuations
//! per first hit. Built once per film; the integrators
//! (`transport::fast`, `transport::lecture`) only read it.

//! Its one `impl` builds it; the estimators' entry points, one per use,
//! are the functions of `transport` (`transport/mod.rs`).

use std::sync::Arc;

use crate::course::RenderSettings;
use crate::geometry::accel::Accel;
use crate::geometry::camera::CameraRays;
use crate::scene::{Camera, Scene};
use crate::transport::continuations::Continuations;
use crate::transport::lights::LightTable;

/// Everything a sample needs: the scene, its acceleration structure, its
/// lights and the settings they were built for.
pub struct RenderContext {
    pub scene: Arc<Scene>,
    pub accel: Accel,
    pub lights: LightTable,
    pub settings: RenderSettings,
    pub camera: CameraRays,
    /// Continuations per first hit the samples take: `settings.indirect_samples`,
    /// or the pilot's choice, region by region, with
    /// `settings.auto_indirect_samples` (`splitting`).
    pub continuations: Continuations,
    /// How far the path log draws a ray that left the scene: one scene
    /// diagonal (at least 1 m), found once, not per ray (it reads every vertex).
    pub escape_length: f32,
}

impl RenderContext {
    /// Builds the lights and the BVH of `scene` for `settings`, with the scene's default camera.
    pub fn new(scene: impl Into<Arc<Scene>>, settings: RenderSettings) -> Self {
        Self::with_camera(scene, settings, None)
    }

    /// [`RenderContext::new`] through `camera` (`None`: the scene's default
    /// one). The continuations per first hit are `settings.indirect_samples`;
    /// with `auto_indirect_samples` the caller runs the splitting pilot once
    /// the settings and the camera are final
    /// ([`crate::transport::splitting::choose_continuations`]).
    pub fn with_camera(
        scene: impl Into<Arc<Scene>>,
        settings: RenderSettings,
        camera: Option<&Camera>,
    ) -> Self {
        // a source switched off emits nothing, in every term
        let scene = crate::transport::sources::switch_off(scene.into(), &settings);
        let lights = LightTable::build(&scene, &settings);
        let accel = Accel::build(&scene, |t| !lights.is_hidden(t), lights.spheres.clone());
        let camera = match camera {
            Some(camera) => CameraRays::new(camera, settings.width, settings.height),
            None => CameraRays::new(&scene.default_camera(), settings.width, settings.height),
        };
        let escape_length = scene.bounds().diagonal().max(1.0);
        Self {
            escape_length,
            scene,
            accel,
            lights,
            continuations: Continuations::uniform(settings.indirect_samples),
            settings,
            camera,
        }
    }

    /// Renders through `camera` from now on; the continuations per first
    /// hit stay as they are (a film's samples must all take the same).
    pub fn set_camera(&mut self, camera: &Camera) {
        self.camera = CameraRays::new(camera, self.settings.width, self.settings.height);
    }
}
