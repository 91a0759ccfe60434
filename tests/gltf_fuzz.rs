//! Fuzzing the glTF loader: mutants of the valid corpus, of the built-in
//! Cornell box and of small GLB containers must each load or be refused,
//! never panic, hang or yield a scene whose render has invalid samples (NaN,
//! infinite or negative radiance, which the film's guard counts).
//!
//! The mutator is hand-rolled and driven by a fixed-seed SplitMix64, so a
//! failure names an iteration that reproduces exactly. Mutations: byte
//! flips, truncations, textual number swaps (huge, negative, fractional,
//! overflowing counts, offsets and indices), JSON-tree edits (a key removed
//! or duplicated, a number made extreme, a value of the wrong type), and GLB
//! length fields rewritten.

mod common;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use lumiere::scene::gltf::load_slice;
use lumiere::scene::{Scene, builtin};
use lumiere::{Film, RenderContext, TermSet};
use serde_json::Value;

/// Mutants per input file (`LUMIERE_FUZZ_MUTANTS` overrides it for a longer search).
const MUTANTS_PER_INPUT: usize = 1000;
/// One mutant in this many also goes through a file and `builtin::load`, as the CLI loads.
const THROUGH_FILE_EVERY: usize = 10;
/// The seed (`LUMIERE_FUZZ_SEED` overrides it for a search elsewhere).
const SEED: u64 = 0x006c_756d_6965_7265; // "lumiere"
/// Longest a single load (and its 8×8 render) may take.
const MAX_LOAD_TIME: Duration = Duration::from_secs(2);

/// SplitMix64: a fixed seed gives the same mutants on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers that break naive loaders: zero, negative, just past a limit, beyond u32, f32 overflow.
const EXTREME_NUMBERS: [&str; 14] = [
    "0",
    "-1",
    "1",
    "3",
    "7",
    "255",
    "65536",
    "2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "1e39",
    "-1e39",
    "0.5",
];

// ---------------------------------------------------------------------------
// Mutations

fn extreme_number(rng: &mut Rng) -> Value {
    let text: &&str = rng.pick(&EXTREME_NUMBERS);
    serde_json::from_str(text).unwrap()
}

fn flip_bytes(bytes: &mut [u8], rng: &mut Rng) {
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(bytes.len());
        bytes[at] ^= 1 << rng.below(8);
    }
}

fn truncate(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let keep = rng.below(bytes.len());
    bytes.truncate(keep);
}

/// Replaces one run of digits in the text (a count, offset, index or value) with an extreme number.
fn swap_number(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let starts: Vec<usize> = (0..bytes.len())
        .filter(|&i| bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_digit()))
        .collect();
    if starts.is_empty() {
        return flip_bytes(bytes, rng);
    }
    let start = *rng.pick(&starts);
    let end = (start..bytes.len())
        .find(|&i| !bytes[i].is_ascii_digit())
        .unwrap_or(bytes.len());
    let number = rng.pick(&EXTREME_NUMBERS).as_bytes();
    bytes.splice(start..end, number.iter().copied());
}

/// Parses the JSON, edits one place of the tree, writes it back (NUL-free, so GLB framing is lost: used on .gltf text only).
fn edit_json_tree(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let Ok(mut root) = serde_json::from_slice::<Value>(bytes) else {
        return flip_bytes(bytes, rng);
    };
    let places = count_values(&root);
    let target = rng.below(places);
    let edit = rng.below(4);
    let mut duplicate = None;
    edit_value(&mut root, target, edit, rng, &mut 0, &mut duplicate);
    let mut text = root.to_string();
    if let Some((key, value)) = duplicate {
        // serde_json's maps hold each key once: the duplicate is written as text, after the first "{"
        let entry = format!("{}:{},", Value::String(key), value);
        if let Some(open) = text.find('{') {
            text.insert_str(open + 1, &entry);
        }
    }
    *bytes = text.into_bytes();
}

fn count_values(value: &Value) -> usize {
    1 + match value {
        Value::Array(items) => items.iter().map(count_values).sum(),
        Value::Object(map) => map.values().map(count_values).sum(),
        _ => 0,
    }
}

/// Edits the `target`-th value in pre-order: 0 removes a key (of an object), 1 duplicates
/// one (reported in `duplicate`), 2 makes a number extreme, 3 changes the value's type.
fn edit_value(
    value: &mut Value,
    target: usize,
    edit: usize,
    rng: &mut Rng,
    seen: &mut usize,
    duplicate: &mut Option<(String, Value)>,
) -> bool {
    if *seen == target {
        match (edit, &mut *value) {
            (0, Value::Object(map)) if !map.is_empty() => {
                let key = map.keys().nth(rng.below(map.len())).cloned().unwrap();
                map.remove(&key);
            }
            (1, Value::Object(map)) if !map.is_empty() => {
                let (key, old) = map.iter().nth(rng.below(map.len())).unwrap();
                let other = if rng.below(2) == 0 {
                    old.clone()
                } else {
                    extreme_number(rng)
                };
                *duplicate = Some((key.clone(), other));
            }
            (3, _) => {
                *value = rng
                    .pick(&[
                        Value::Null,
                        Value::Bool(true),
                        Value::String("x".into()),
                        Value::Array(Vec::new()),
                        Value::Object(Default::default()),
                    ])
                    .clone();
            }
            _ => *value = extreme_number(rng),
        }
        return true;
    }
    *seen += 1;
    match value {
        Value::Array(items) => items
            .iter_mut()
            .any(|item| edit_value(item, target, edit, rng, seen, duplicate)),
        Value::Object(map) => map
            .values_mut()
            .any(|item| edit_value(item, target, edit, rng, seen, duplicate)),
        _ => false,
    }
}

/// Rewrites one of a GLB's length fields: the total, the JSON chunk's or the BIN chunk's.
fn lie_in_glb_header(bytes: &mut [u8], rng: &mut Rng) {
    let json_length = read_u32(bytes, 12) as usize;
    let bin_at = 20 + json_length;
    let mut fields = vec![8, 12];
    if bin_at + 4 <= bytes.len() {
        fields.push(bin_at);
    }
    let at = *rng.pick(&fields);
    let old = read_u32(bytes, at);
    let new = match rng.below(6) {
        0 => 0,
        1 => u32::MAX,
        2 => old.wrapping_add(4),
        3 => old.wrapping_sub(4),
        4 => old.wrapping_add(1),
        _ => rng.next() as u32,
    };
    bytes[at..at + 4].copy_from_slice(&new.to_le_bytes());
}

fn read_u32(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

fn mutate(original: &[u8], is_glb: bool, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = original.to_vec();
    let kinds = if is_glb { 5 } else { 4 };
    match rng.below(kinds) {
        0 => flip_bytes(&mut bytes, rng),
        1 => truncate(&mut bytes, rng),
        2 => swap_number(&mut bytes, rng),
        3 if is_glb => swap_number(&mut bytes, rng),
        3 => edit_json_tree(&mut bytes, rng),
        _ => lie_in_glb_header(&mut bytes, rng),
    }
    bytes
}

// ---------------------------------------------------------------------------
// Inputs

/// An indexed triangle with normals in a GLB's BIN chunk.
fn triangle_glb() -> Vec<u8> {
    let json = br#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"rotation":[0,0,0,1]}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":0,"byteOffset":36,"componentType":5126,"count":3,"type":"VEC3"},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],
"bufferViews":[{"buffer":0,"byteLength":72,"byteStride":12},{"buffer":0,"byteOffset":72,"byteLength":6}],
"buffers":[{"byteLength":78}]}"#;
    let mut bin: Vec<u8> = [
        0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ]
    .iter()
    .flat_map(|v| v.to_le_bytes())
    .collect();
    bin.extend([0u16, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
    common::glb(json, Some(&bin))
}

/// (name, bytes) of every input: the valid corpus, the Cornell box and its
/// glass variant, and GLB containers.
fn inputs() -> Vec<(String, Vec<u8>)> {
    let mut inputs = Vec::new();
    for path in common::gltf_files(&common::corpus_dir().join("valid")) {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        inputs.push((name, std::fs::read(&path).unwrap()));
    }
    let cornell =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cornell-box.gltf"))
            .unwrap();
    inputs.push(("cornell-box.glb".into(), common::glb(&cornell, None)));
    inputs.push(("cornell-box.gltf".into(), cornell));
    // glass: KHR_materials_transmission and KHR_materials_ior
    let glass = builtin::SCENES
        .iter()
        .find(|s| s.name == "cornell-glass")
        .unwrap()
        .gltf();
    inputs.push(("cornell-glass.gltf".into(), glass.to_vec()));
    inputs.push(("triangle.glb".into(), triangle_glb()));
    inputs
}

// ---------------------------------------------------------------------------
// The check of one mutant

/// Loads `bytes` (panics caught), and renders an 8×8 pass of what loads.
/// Returns whether it loaded, or a failure description.
fn check(bytes: &[u8], name: &str, through_file: Option<&Path>) -> Result<bool, String> {
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let loaded = match through_file {
            Some(path) => {
                std::fs::write(path, bytes).unwrap();
                builtin::load(path.to_str().unwrap())
            }
            None => load_slice(bytes, name, None),
        };
        match loaded {
            Ok(scene) => render_one_pass(scene).map(|()| true),
            Err(error) => {
                let message = error.to_string();
                // the loader catches the crate's panics itself: one caught is a check missing
                if message.contains("the glTF reader failed") {
                    Err(format!("caught panic: {message}"))
                } else {
                    Ok(false)
                }
            }
        }
    }));
    let elapsed = start.elapsed();
    match outcome {
        Err(_) => Err("panicked".into()),
        Ok(Ok(_)) if elapsed > MAX_LOAD_TIME => Err(format!("took {elapsed:?}")),
        Ok(result) => result,
    }
}

fn render_one_pass(scene: Scene) -> Result<(), String> {
    let settings = common::small(8, 8, TermSet::ALL);
    let context = RenderContext::new(scene, settings.clone());
    let mut film = Film::new(8, 8);
    let stats = lumiere::render::render(
        &context,
        &mut film,
        lumiere::render::Budget::Samples(1),
        |_| {},
    );
    // the film's guard zeroes NaN, infinite and negative samples: its count shows them
    match stats.rays.invalid_samples {
        0 => Ok(()),
        n => Err(format!("{n} invalid samples (NaN, infinite or negative)")),
    }
}

#[test]
fn mutated_files_load_or_are_refused_without_panic_hang_or_invalid_samples() {
    let started = Instant::now();
    let directory = std::env::temp_dir().join(format!("lumiere-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let setting = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .map_or(default, |v| v.parse().expect("a number"))
    };
    let mut rng = Rng(setting("LUMIERE_FUZZ_SEED", SEED));
    let mutants_per_input = setting("LUMIERE_FUZZ_MUTANTS", MUTANTS_PER_INPUT as u64) as usize;
    let mut failures = Vec::new();
    let (mut loaded, mut refused, mut total) = (0usize, 0usize, 0usize);
    for (name, original) in inputs() {
        assert_eq!(check(&original, &name, None), Ok(true), "{name} itself");
        let is_glb = original.starts_with(b"glTF");
        for i in 0..mutants_per_input {
            let mutant = mutate(&original, is_glb, &mut rng);
            let file: Option<PathBuf> =
                (i % THROUGH_FILE_EVERY == 0).then(|| directory.join(&name));
            total += 1;
            match check(&mutant, &name, file.as_deref()) {
                Ok(true) => loaded += 1,
                Ok(false) => refused += 1,
                Err(failure) => {
                    let kept = directory.join(format!("failure-{i}-{name}"));
                    std::fs::write(&kept, &mutant).unwrap();
                    failures.push(format!("{name} mutant {i} ({}): {failure}", kept.display()));
                }
            }
        }
    }
    eprintln!(
        "{total} mutants: {loaded} loaded, {refused} refused, {} failed, in {:.1} s",
        failures.len(),
        started.elapsed().as_secs_f64()
    );
    if failures.is_empty() {
        let _ = std::fs::remove_dir_all(&directory);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
