//! The cached binary artifact: round trip, zero-copy loading, detection of every kind of
//! corruption, the cache's rebuild policy, atomic concurrent writes and cache-key
//! sensitivity.

use std::cell::Cell;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use flexflight::artifact::container::{
    OFFSET_CHECKSUM, OFFSET_KEY, OFFSET_PAYLOAD_LEN, OFFSET_VERSION,
};
use flexflight::artifact::{
    Artifact, ArtifactError, ArtifactPayload, Cache, CacheKey, CacheKeyBuilder, CacheOutcome,
    GetOrBuildError, HEADER_LEN, load, write_atomic,
};
use rkyv::rancor;

/// A stand-in for the structural model: one large array and some nested fields.
#[derive(rkyv::Archive, rkyv::Serialize, rkyv::Deserialize, Debug, Clone, PartialEq)]
struct TestModel {
    name: String,
    samples: Vec<f64>,
    nodes: Vec<TestNode>,
    reduced: TestReduced,
}

#[derive(rkyv::Archive, rkyv::Serialize, rkyv::Deserialize, Debug, Clone, PartialEq)]
struct TestNode {
    id: u32,
    position_m: [f64; 3],
}

#[derive(rkyv::Archive, rkyv::Serialize, rkyv::Deserialize, Debug, Clone, PartialEq)]
struct TestReduced {
    frequencies_hz: Vec<f64>,
    note: Option<String>,
}

impl ArtifactPayload for TestModel {
    const SCHEMA: &'static str = "TestModel v1: name String, samples Vec<f64>, \
        nodes Vec<{id u32, position_m [f64;3]}>, reduced {frequencies_hz Vec<f64>, note Option<String>}";
}

/// The same layout under another schema description: a stale payload type.
#[derive(rkyv::Archive, rkyv::Serialize, rkyv::Deserialize, Debug, Clone, PartialEq)]
struct TestModelV2(TestModel);

impl ArtifactPayload for TestModelV2 {
    const SCHEMA: &'static str = "TestModel v2: as v1 but samples in mm";
}

fn model(sample_count: usize) -> TestModel {
    TestModel {
        name: "sounding rocket".to_owned(),
        samples: (0..sample_count)
            .map(|i| (i as f64 * 0.001).sin() * 1.0e3 + i as f64)
            .collect(),
        nodes: (0..40)
            .map(|i| TestNode {
                id: i,
                position_m: [-(i as f64) * 0.25, 0.01 * i as f64, -0.5],
            })
            .collect(),
        reduced: TestReduced {
            frequencies_hz: vec![12.5, 31.25, 47.0, 88.125],
            note: Some("fin flap pair".to_owned()),
        },
    }
}

fn key(tag: &str) -> CacheKey {
    CacheKeyBuilder::new("test-model")
        .text("case", tag)
        .finish()
}

fn deserialize(artifact: &Artifact<TestModel>) -> TestModel {
    rkyv::deserialize::<TestModel, rancor::Error>(artifact.get()).expect("deserialise")
}

/// Writes a small valid artifact and returns its path and key.
fn small_artifact(dir: &Path) -> (PathBuf, CacheKey) {
    let key = key("small");
    let path = write_atomic(dir, &key, &model(10_000)).expect("write");
    (path, key)
}

fn code_of(result: Result<Artifact<TestModel>, ArtifactError>) -> &'static str {
    match result {
        Ok(_) => "accepted",
        Err(error) => error.code(),
    }
}

fn patch(path: &Path, offset: usize, bytes: &[u8]) {
    let mut contents = fs::read(path).expect("read");
    contents[offset..offset + bytes.len()].copy_from_slice(bytes);
    fs::write(path, contents).expect("write");
}

fn flip(path: &Path, offset: usize) {
    let byte = fs::read(path).expect("read")[offset];
    patch(path, offset, &[byte ^ 0x10]);
}

#[test]
fn round_trip_preserves_every_field() {
    let dir = tempfile::tempdir().expect("tempdir");
    let original = model(1_000_000);
    let key = key("round trip");
    let path = write_atomic(dir.path(), &key, &original).expect("write");
    assert_eq!(
        path.file_name().and_then(|n| n.to_str()),
        Some(format!("{key}.ffa").as_str())
    );
    let artifact = load::<TestModel>(&path, &key).expect("load");
    assert!(artifact.is_mapped());
    assert_eq!(artifact.path(), Some(path.as_path()));
    assert_eq!(deserialize(&artifact), original);
    let archived = artifact.get();
    assert_eq!(archived.samples.len(), 1_000_000);
    assert_eq!(
        archived.samples[123_456].to_native(),
        original.samples[123_456]
    );
    assert_eq!(archived.reduced.note.as_deref(), Some("fin flap pair"));
}

#[test]
fn loading_maps_the_arrays_without_copying() {
    let dir = tempfile::tempdir().expect("tempdir");
    let key = key("zero copy");
    let path = write_atomic(dir.path(), &key, &model(1_000_000)).expect("write");
    let artifact = load::<TestModel>(&path, &key).expect("load");
    let file_len = fs::metadata(&path).expect("metadata").len() as usize;
    let mapped = artifact.all_bytes().as_ptr_range();
    assert_eq!(artifact.all_bytes().len(), file_len);
    let samples = artifact.get().samples.as_slice().as_ptr_range();
    assert!(
        mapped.start as usize + HEADER_LEN <= samples.start as usize
            && samples.end as usize <= mapped.end as usize,
        "samples {samples:?} lie outside the mapping {mapped:?}"
    );
    assert_eq!(
        samples.end as usize - samples.start as usize,
        1_000_000 * size_of::<f64>()
    );
    // The checked access sees the same bytes.
    let checked = artifact.get_checked().expect("re-validation");
    assert_eq!(checked.samples.as_slice().as_ptr(), samples.start);
}

#[test]
fn flipped_payload_byte_is_a_checksum_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, key) = small_artifact(dir.path());
    let len = fs::metadata(&path).expect("metadata").len() as usize;
    flip(&path, HEADER_LEN + (len - HEADER_LEN) / 2);
    assert_eq!(code_of(load(&path, &key)), "artifact::checksum");
}

#[test]
fn flipped_header_bytes_are_detected() {
    let dir = tempfile::tempdir().expect("tempdir");
    // (offset, expected code): magic, reserved, schema, key, length, reserved, checksum.
    let cases = [
        (0, "artifact::bad_magic"),
        (7, "artifact::bad_magic"),
        (OFFSET_VERSION, "artifact::version"),
        (12, "artifact::checksum"),
        (20, "artifact::schema"),
        (OFFSET_KEY + 31, "artifact::key_mismatch"),
        (OFFSET_PAYLOAD_LEN + 2, "artifact::truncated"),
        (90, "artifact::checksum"),
        (OFFSET_CHECKSUM + 5, "artifact::checksum"),
    ];
    for (offset, expected) in cases {
        let (path, key) = small_artifact(dir.path());
        flip(&path, offset);
        assert_eq!(
            code_of(load(&path, &key)),
            expected,
            "flipped byte {offset}"
        );
    }
}

#[test]
fn truncated_and_extended_files_are_detected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, key) = small_artifact(dir.path());
    let full = fs::read(&path).expect("read");
    for cut in [
        full.len() - 1,
        full.len() / 2,
        HEADER_LEN,
        HEADER_LEN - 1,
        7,
        0,
    ] {
        fs::write(&path, &full[..cut]).expect("write");
        assert_eq!(
            code_of(load(&path, &key)),
            "artifact::truncated",
            "cut at {cut}"
        );
    }
    let mut longer = full.clone();
    longer.extend_from_slice(&[0; 16]);
    fs::write(&path, &longer).expect("write");
    assert_eq!(code_of(load(&path, &key)), "artifact::trailing_bytes");
}

#[test]
fn other_format_version_is_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, key) = small_artifact(dir.path());
    patch(&path, OFFSET_VERSION, &2u32.to_le_bytes());
    let error = load::<TestModel>(&path, &key).expect_err("must reject");
    assert_eq!(error.code(), "artifact::version");
    assert_eq!(error.path(), path.as_path());
}

#[test]
fn other_schema_is_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let key = key("schema");
    let path = write_atomic(dir.path(), &key, &TestModelV2(model(100))).expect("write");
    assert_eq!(code_of(load::<TestModel>(&path, &key)), "artifact::schema");
    assert!(load::<TestModelV2>(&path, &key).is_ok());
}

#[test]
fn other_key_is_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, _key) = small_artifact(dir.path());
    assert_eq!(
        code_of(load(&path, &key("another"))),
        "artifact::key_mismatch"
    );
}

#[test]
fn valid_checksum_over_garbage_payload_fails_validation() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, key) = small_artifact(dir.path());
    let mut contents = fs::read(&path).expect("read");
    let payload_len = contents.len() - HEADER_LEN;
    contents[HEADER_LEN..].copy_from_slice(&vec![0xff; payload_len]);
    let mut hasher = blake3::Hasher::new();
    hasher.update(&contents[..OFFSET_CHECKSUM]);
    hasher.update(&contents[HEADER_LEN..]);
    let checksum = *hasher.finalize().as_bytes();
    contents[OFFSET_CHECKSUM..OFFSET_CHECKSUM + 32].copy_from_slice(&checksum);
    fs::write(&path, &contents).expect("write");
    assert_eq!(code_of(load(&path, &key)), "artifact::invalid_payload");
}

#[test]
fn missing_file_is_a_not_found_io_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    match load::<TestModel>(&dir.path().join("absent.ffa"), &key("absent")) {
        Err(ArtifactError::Io { source, .. }) => {
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound)
        }
        other => panic!("expected io error, got {other:?}"),
    }
}

#[test]
fn get_or_build_misses_hits_and_rebuilds_after_corruption() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = Cache::new(dir.path().join("cache"));
    let key = key("get or build");
    let original = model(50_000);
    let builds = Cell::new(0);
    let build = || {
        builds.set(builds.get() + 1);
        Ok::<_, String>(original.clone())
    };

    let (artifact, outcome) = cache.get_or_build(&key, build).expect("miss");
    assert!(matches!(outcome, CacheOutcome::Miss), "{outcome}");
    assert_eq!(deserialize(&artifact), original);
    drop(artifact);

    let (artifact, outcome) = cache.get_or_build(&key, build).expect("hit");
    assert!(outcome.is_hit(), "{outcome}");
    assert_eq!(builds.get(), 1);
    drop(artifact);

    let path = cache.path_for(&key);
    let len = fs::metadata(&path).expect("metadata").len() as usize;
    flip(&path, len - 3);
    let (artifact, outcome) = cache.get_or_build(&key, build).expect("rebuild");
    match &outcome {
        CacheOutcome::Rebuilt { reason } => assert_eq!(reason.code(), "artifact::checksum"),
        other => panic!("expected a rebuild, got {other}"),
    }
    assert!(outcome.to_string().contains("artifact::checksum"));
    assert_eq!(builds.get(), 2);
    assert_eq!(deserialize(&artifact), original);
    drop(artifact);

    let (_artifact, outcome) = cache.get_or_build(&key, build).expect("hit after rebuild");
    assert!(outcome.is_hit(), "{outcome}");
    assert_eq!(builds.get(), 2);
}

#[test]
fn get_or_build_replaces_a_truncated_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = Cache::new(dir.path());
    let key = key("truncated in cache");
    fs::write(cache.path_for(&key), b"FLEXFLT\0").expect("write");
    let (artifact, outcome) = cache
        .get_or_build(&key, || Ok::<_, String>(model(10)))
        .expect("rebuild");
    match outcome {
        CacheOutcome::Rebuilt { reason } => assert_eq!(reason.code(), "artifact::truncated"),
        other => panic!("expected a rebuild, got {other}"),
    }
    assert_eq!(deserialize(&artifact), model(10));
}

#[test]
fn failing_build_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache_dir = dir.path().join("cache");
    let cache = Cache::new(&cache_dir);
    let result = cache.get_or_build::<TestModel, _>(&key("failing"), || {
        Err("mass matrix not positive definite".to_owned())
    });
    match result {
        Err(GetOrBuildError::Build(message)) => assert!(message.contains("positive definite")),
        other => panic!("expected the build error, got {other:?}"),
    }
    assert!(!cache_dir.exists(), "the cache directory was created");

    fs::create_dir_all(&cache_dir).expect("mkdir");
    let result = cache.get_or_build::<TestModel, _>(&key("failing"), || Err("again".to_owned()));
    assert!(matches!(result, Err(GetOrBuildError::Build(_))));
    assert_eq!(fs::read_dir(&cache_dir).expect("read dir").count(), 0);
}

#[test]
fn concurrent_writers_of_one_key_leave_a_valid_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let key = key("concurrent");
    let value = model(200_000);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                for _ in 0..10 {
                    let path = write_atomic(dir.path(), &key, &value).expect("write");
                    // A reader at any moment sees a complete artifact.
                    let artifact = load::<TestModel>(&path, &key).expect("load during writes");
                    assert_eq!(artifact.get().samples.len(), 200_000);
                }
            });
        }
    });
    let names: Vec<_> = fs::read_dir(dir.path())
        .expect("read dir")
        .map(|entry| entry.expect("entry").file_name())
        .collect();
    assert_eq!(names.len(), 1, "temporary files left behind: {names:?}");
    let artifact = load::<TestModel>(&dir.path().join(&names[0]), &key).expect("load");
    assert_eq!(deserialize(&artifact), value);
}

#[test]
fn in_memory_artifact_needs_no_file() {
    let original = model(1_000);
    let artifact = Artifact::from_value(&original).expect("serialise");
    assert!(!artifact.is_mapped());
    assert_eq!(artifact.path(), None);
    assert_eq!(deserialize(&artifact), original);
}

#[test]
fn cache_key_changes_with_every_input() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mesh = dir.path().join("mesh.json");
    fs::write(&mesh, b"{\"nodes\": 12}").expect("write");
    let with = |edit: &dyn Fn(&mut CacheKeyBuilder)| {
        let mut builder = CacheKeyBuilder::new("structural-model");
        builder
            .text("vehicle", "body L=3.2")
            .bytes("options", &[1, 2, 3])
            .f64("damping", 0.02)
            .u64("modes", 12);
        builder.file("mesh", &mesh).expect("hash file");
        edit(&mut builder);
        builder.finish()
    };
    let base = with(&|_| {});
    assert_eq!(base, with(&|_| {}), "the key is deterministic");
    assert_eq!(base.to_string().len(), 64);
    assert!(base.to_string().chars().all(|c| c.is_ascii_hexdigit()));

    let mut keys = vec![base];
    keys.push(with(&|b| {
        b.text("extra", "");
    }));
    keys.push(with(&|b| {
        b.text("", "extra");
    }));
    keys.push(with(&|b| {
        b.bytes("extra", b"");
    }));
    keys.push(with(&|b| {
        b.f64("extra", 0.0);
    }));
    keys.push(with(&|b| {
        b.f64("extra", -0.0);
    }));
    keys.push(with(&|b| {
        b.u64("extra", 0);
    }));
    keys.push(CacheKeyBuilder::new("other-kind").finish());
    keys.push(CacheKeyBuilder::new("structural-model").finish());
    let mut sorted = keys.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), keys.len(), "two different inputs share a key");

    // Each single input changes the key: value, label, float bits, bytes, file contents.
    let single = |label: &str, text: &str, damping: f64, bytes: &[u8], file: &Path| {
        let mut builder = CacheKeyBuilder::new("structural-model");
        builder
            .text(label, text)
            .f64("damping", damping)
            .bytes("options", bytes);
        builder.file("mesh", file).expect("hash file");
        builder.finish()
    };
    let reference = single("vehicle", "body L=3.2", 0.02, &[1, 2, 3], &mesh);
    assert_ne!(
        reference,
        single("vehicle", "body L=3.3", 0.02, &[1, 2, 3], &mesh)
    );
    assert_ne!(
        reference,
        single("vehicles", "body L=3.2", 0.02, &[1, 2, 3], &mesh)
    );
    assert_ne!(
        reference,
        single(
            "vehicle",
            "body L=3.2",
            0.020000000000000004,
            &[1, 2, 3],
            &mesh
        )
    );
    assert_ne!(
        reference,
        single("vehicle", "body L=3.2", 0.02, &[1, 2, 4], &mesh)
    );
    let moved = dir.path().join("mesh-copy.json");
    fs::copy(&mesh, &moved).expect("copy");
    assert_ne!(
        reference,
        single("vehicle", "body L=3.2", 0.02, &[1, 2, 3], &moved)
    );
    fs::write(&mesh, b"{\"nodes\": 13}").expect("write");
    assert_ne!(
        reference,
        single("vehicle", "body L=3.2", 0.02, &[1, 2, 3], &mesh)
    );
    fs::write(&mesh, b"{\"nodes\": 12}").expect("write");
    assert_eq!(
        reference,
        single("vehicle", "body L=3.2", 0.02, &[1, 2, 3], &mesh)
    );

    assert!(
        CacheKeyBuilder::new("x")
            .file("mesh", &dir.path().join("absent"))
            .is_err()
    );
}

#[test]
fn cache_key_inputs_are_length_prefixed() {
    let key_of = |parts: &[(&str, &str)]| {
        let mut builder = CacheKeyBuilder::new("structural-model");
        for (label, value) in parts {
            builder.text(label, value);
        }
        builder.finish()
    };
    assert_ne!(
        key_of(&[("x", "ab"), ("y", "c")]),
        key_of(&[("x", "a"), ("y", "bc")])
    );
    assert_ne!(key_of(&[("ab", "c")]), key_of(&[("a", "bc")]));
    assert_ne!(key_of(&[("a", "b"), ("c", "")]), key_of(&[("a", "b")]));
    // Text and bytes of the same content are different inputs.
    let text = CacheKeyBuilder::new("k").text("v", "abc").finish();
    let bytes = CacheKeyBuilder::new("k").bytes("v", b"abc").finish();
    assert_ne!(text, bytes);
}

#[test]
fn cache_directory_precedence() {
    use std::ffi::OsString;
    let cli = Path::new("/from/cli");
    let env = || Some(OsString::from("/from/env"));
    let target = || Some(OsString::from("/cargo/target"));
    assert_eq!(Cache::resolve_from(Some(cli), env(), target()).dir(), cli);
    assert_eq!(
        Cache::resolve_from(None, env(), target()).dir(),
        Path::new("/from/env")
    );
    assert_eq!(
        Cache::resolve_from(None, None, target()).dir(),
        Path::new("/cargo/target/flexflight-cache")
    );
    assert_eq!(
        Cache::resolve_from(None, Some(OsString::new()), None).dir(),
        Path::new("target/flexflight-cache")
    );
}

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

/// Cache-hit time of a ~10 MB artifact. Run with optimisation for meaningful figures:
/// `CARGO_PROFILE_DEV_OPT_LEVEL=3 cargo test --test artifact -- --ignored --nocapture`.
#[test]
#[ignore = "timing; run explicitly with optimisation"]
fn cache_hit_of_10_mb_artifact_is_under_20_ms() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = Cache::new(dir.path());
    let key = key("timing");
    let value = model(1_250_000);
    let started = Instant::now();
    let (artifact, outcome) = cache
        .get_or_build(&key, || Ok::<_, String>(value.clone()))
        .expect("build");
    let miss = started.elapsed();
    assert!(matches!(outcome, CacheOutcome::Miss));
    let file_len = artifact.all_bytes().len();
    drop(artifact);

    let mut hits = Vec::new();
    let mut checked = Vec::new();
    let mut gets = Vec::new();
    for _ in 0..21 {
        let started = Instant::now();
        let (artifact, outcome) = cache
            .get_or_build(&key, || Err::<TestModel, _>("must not build".to_owned()))
            .expect("hit");
        hits.push(started.elapsed());
        assert!(outcome.is_hit());
        let started = Instant::now();
        let sum: f64 = artifact
            .get()
            .samples
            .iter()
            .take(1)
            .map(|x| x.to_native())
            .sum();
        gets.push(started.elapsed());
        std::hint::black_box(sum);
        let started = Instant::now();
        std::hint::black_box(artifact.get_checked().expect("valid"));
        checked.push(started.elapsed());
    }
    let hit = median(hits);
    println!(
        "artifact of {:.1} MB: miss (build+write+load) {miss:?}, hit median {hit:?}, \
         get {:?}, get_checked {:?}",
        file_len as f64 / 1.0e6,
        median(gets),
        median(checked)
    );
    assert!(hit < Duration::from_millis(20), "cache hit took {hit:?}");
}
