//! A peer renderer's error curve, run as a separate program.
//!
//! The contract with the peer's script: it renders `<scene.gltf>` at the
//! given size and sample counts with a path tracer of `--max-depth` segments
//! (3 = L0 + L1 + L2, Mitsuba's convention), measures each image against
//! `--reference <ref.exr>` and writes `<out>.csv` with the columns of
//! [`super::csv::ERROR_COLUMNS`]. A file without a camera, which lumiere
//! frames itself, comes with `--camera`: lumiere's framing camera. A
//! curve extended past its counts (lumiere's rule, `extend_spp`) comes with
//! `--until-relmse τ --spp-limit N`: while the last image's relMSE is above
//! τ, render twice its samples, as long as that is at most N. A
//! missing interpreter, script or package skips the peer with a message; it
//! never fails the bench.

use strum::{Display, EnumIter, EnumString, IntoStaticStr};

use crate::course::unknown_choice;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::course::Choice;
use crate::course::{BrdfOverride, LightMode, RenderSettings, Term};
use crate::scene::{Projection, Scene, builtin};
use crate::transport::lights::sphere_light_radius;

use super::csv::{ErrorRow, read_error_csv};
use super::error_curve::{ErrorBench, lowest_threshold};
use super::{BenchError, Progress};

/// Renderers lumiere can run for comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, EnumIter, IntoStaticStr, EnumString, Display)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Peer>)]
pub enum Peer {
    Mitsuba,
}

impl Peer {
    /// The script, relative to the repository root.
    pub fn script(self) -> &'static str {
        match self {
            Peer::Mitsuba => "tests/reference/mitsuba_bench.py",
        }
    }
}

/// What running a peer gave.
#[derive(Clone, Debug, PartialEq)]
pub enum PeerRun {
    Rows(Vec<ErrorRow>),
    /// Why it did not run, for the summary.
    Skipped(String),
}

/// Path segments of the peer's paths for `settings`' terms, if they are L0 up
/// to some L_k (a peer's path tracer cannot leave out the lower terms).
pub fn max_depth(settings: &RenderSettings) -> Option<u32> {
    let terms = settings.terms;
    let reflections = terms.max_reflections()?.min(settings.max_bounces);
    let prefix = Term::ALL.iter().take_while(|t| terms.contains(**t)).count();
    let contiguous = terms.iter().count() == prefix;
    (contiguous && terms.contains(Term::L0)).then_some(reflections.saturating_add(1))
}

/// The peer's arguments that make it render the scene lumiere renders for
/// `settings`: its `--brdf` and `--lights` overrides (the peer reads the
/// file itself, and maps its materials, lumiere's Phong among them).
pub fn scene_overrides(scene: &Scene, settings: &RenderSettings) -> Vec<String> {
    let mut arguments = Vec::new();
    match settings.light_mode {
        LightMode::Authored => {}
        LightMode::Area => arguments.extend([
            "--sphere-lights".to_string(),
            sphere_light_radius(scene, settings).to_string(),
        ]),
        LightMode::Point => arguments.push("--point-emitters".to_string()),
    }
    match settings.brdf {
        BrdfOverride::Authored => {}
        BrdfOverride::Lambert | BrdfOverride::Mirror => {
            arguments.extend(["--brdf".to_string(), settings.brdf.label().to_string()])
        }
        BrdfOverride::Glass => arguments.extend([
            "--brdf".to_string(),
            "glass".to_string(),
            "--ior".to_string(),
            settings.glass_ior.to_string(),
        ]),
        BrdfOverride::Phong => arguments.extend([
            "--brdf".to_string(),
            "phong".to_string(),
            "--phong-exponent".to_string(),
            settings.phong_exponent.to_string(),
            "--phong-specular".to_string(),
            settings.phong_specular.to_string(),
        ]),
    }
    arguments
}

/// The peer's `--camera` argument for a scene that has no camera of its
/// own, which lumiere frames itself (`Scene::default_camera`): that framing
/// camera, world from camera by rows, then yfov. Empty when the file has a
/// camera (the peer reads it); `Err` for a camera the peer cannot take.
pub fn camera_arguments(scene: &Scene) -> Result<Vec<String>, String> {
    if !scene.cameras.is_empty() {
        return Ok(Vec::new());
    }
    let camera = scene.default_camera();
    let Projection::Perspective { yfov } = camera.projection else {
        return Err("lumiere's framing camera is not a perspective one".into());
    };
    let world = camera.world_from_camera;
    let columns = [
        world.matrix3.x_axis,
        world.matrix3.y_axis,
        world.matrix3.z_axis,
        world.translation,
    ];
    let mut values: Vec<String> = Vec::with_capacity(13);
    for row in 0..3 {
        values.extend(columns.iter().map(|c| c[row].to_string()));
    }
    values.push(yfov.to_string());
    Ok(vec!["--camera".into(), values.join(",")])
}

/// The scene as a glTF file the peer can read: the file itself, or a
/// built-in scene written into `folder`.
fn scene_file(scene: &str, folder: &Path) -> Result<PathBuf, BenchError> {
    let Some(builtin) = builtin::SCENES.iter().find(|s| s.name == scene) else {
        return Ok(PathBuf::from(scene));
    };
    let path = folder.join(format!("{}.gltf", builtin.name));
    std::fs::write(&path, builtin.gltf())
        .map_err(|e| BenchError::file(&path, format!("cannot write: {e}")))?;
    Ok(path)
}

fn find_script(peer: Peer) -> Option<PathBuf> {
    [
        PathBuf::from(peer.script()),
        Path::new(env!("CARGO_MANIFEST_DIR")).join(peer.script()),
    ]
    .into_iter()
    .find(|p| p.is_file())
}

/// Runs `peer` on `bench`'s scene (`loaded`) at its size, terms and overrides, `counts` samples
/// per pixel against `reference`, its CSV written into `folder`.
pub fn run(
    peer: Peer,
    bench: &ErrorBench,
    loaded: &Scene,
    reference: &Path,
    counts: &[u32],
    folder: &Path,
    progress: &dyn Progress,
) -> Result<PeerRun, BenchError> {
    let (scene, settings) = (bench.scene.as_str(), &bench.settings);
    let Some(script) = find_script(peer) else {
        return Ok(PeerRun::Skipped(format!("{} not found", peer.script())));
    };
    let Some(depth) = max_depth(settings) else {
        return Ok(PeerRun::Skipped(format!(
            "terms {} are not L0 up to some L_k, which {} cannot render",
            settings.terms,
            peer.label()
        )));
    };
    let overrides = scene_overrides(loaded, settings);
    let camera = match camera_arguments(loaded) {
        Ok(arguments) => arguments,
        Err(reason) => {
            return Ok(PeerRun::Skipped(format!(
                "{} not run: {reason}",
                peer.label()
            )));
        }
    };
    let scene_path = scene_file(scene, folder)?;
    let csv = folder.join(format!("{}.csv", peer.label()));
    let spp: Vec<String> = counts.iter().map(u32::to_string).collect();
    progress.message(&format!("error: {} at {} spp", peer.label(), spp.join(",")));
    let mut command = Command::new("python3");
    command
        .arg(&script)
        .arg(&scene_path)
        .arg("--reference")
        .arg(reference)
        .args(["--width", &settings.width.to_string()])
        .args(["--height", &settings.height.to_string()])
        .args(["--max-depth", &depth.to_string()])
        .args(["--spp", &spp.join(",")])
        .args(&overrides)
        .args(&camera)
        .arg("--out")
        .arg(&csv);
    if bench.extend_spp > counts.last().copied().unwrap_or(0) {
        command
            .args(["--until-relmse", &lowest_threshold().to_string()])
            .args(["--spp-limit", &bench.extend_spp.to_string()]);
    }
    let output = command.output();
    let output = match output {
        Ok(output) => output,
        Err(e) => return Ok(PeerRun::Skipped(format!("cannot run python3: {e}"))),
    };
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Ok(PeerRun::Skipped(format!(
            "{} failed ({}): {last}",
            peer.script(),
            output.status
        )));
    }
    Ok(PeerRun::Rows(read_error_csv(&csv)?))
}
