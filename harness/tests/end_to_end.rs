//! compare and sweep end to end through the library, on a 32x32 image, with small private test
//! techniques (a constant clear, a NaN image, a failing one, one needing a missing feature)
//! and a constant ground truth, so the numbers are known exactly.

use gpu::wgpu;
use gpu::{HdrImage, Target};
use harness::compare::CompareOptions;
use harness::engine::ExecOptions;
use harness::sweep::SweepOptions;
use harness::{Env, Frames, GroundTruth, Reference, ReferenceStats, Size};
use scene::{
    Camera, Frame, GpuScene, Param, Scene, Technique, TechniqueError, TechniqueResult, View,
};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("harness-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

const SIZE: Size = Size::new(32, 32);
/// cornell-sphere's camera path lasts 2 s: error frames at times 0, 1 and 2.
const FRAMES: Frames = Frames {
    timed: 3,
    warmup: 1,
    errors: 3,
    timed_budget_s: 0.0,
};

/// Clears the target to `level` in every colour channel.
struct Constant {
    id: &'static str,
    level: f64,
    /// Change of the level per second of scene time (a technique whose error moves).
    drift: f64,
    /// Slows every render down and records the times asked for, where set.
    pace: Option<Pace>,
}

/// How long each render of a [`Constant`] takes at least, and the view times it rendered.
struct Pace {
    sleep: std::time::Duration,
    renders: std::sync::Arc<std::sync::Mutex<Vec<f32>>>,
}

impl Technique for Constant {
    fn id(&self) -> String {
        self.id.into()
    }
    fn description(&self) -> String {
        "clears to a constant".into()
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "level",
            default: 0.25,
            min: 0.0,
            max: 4.0,
            integer: false,
            help: "the constant",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        scene::technique::check_param(&self.id(), &self.params(), name, value)?;
        self.level = value;
        Ok(())
    }
    fn supports(&self, _: &Scene) -> bool {
        true
    }
    fn prepare(&mut self, _: &mut Frame, _: &GpuScene) -> TechniqueResult<()> {
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        _: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        if let Some(pace) = &self.pace {
            std::thread::sleep(pace.sleep);
            pace.renders.lock().unwrap().push(view.time);
        }
        let l = self.level + self.drift * view.time as f64;
        let timestamps = frame.timer.render_pass("clear");
        let _pass = frame
            .encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("clear"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: l,
                            g: l,
                            b: l,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        Ok(())
    }
}

/// Writes NaN into every pixel.
struct NanImage;

impl Technique for NanImage {
    fn id(&self) -> String {
        "test/nan".into()
    }
    fn description(&self) -> String {
        "NaN everywhere".into()
    }
    fn supports(&self, _: &Scene) -> bool {
        true
    }
    fn prepare(&mut self, _: &mut Frame, _: &GpuScene) -> TechniqueResult<()> {
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        _: &GpuScene,
        _: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let texels = vec![[f32::NAN, 0.0, 0.0, 1.0]; (target.width * target.height) as usize];
        frame.gpu.queue.write_texture(
            target.color.as_image_copy(),
            &texels
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect::<Vec<u8>>(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(16 * target.width),
                rows_per_image: None,
            },
            target.color.size(),
        );
        Ok(())
    }
}

/// Fails in render, or panics, or declares a feature no device of the context has, or supports nothing.
struct Broken {
    id: &'static str,
}

impl Technique for Broken {
    fn id(&self) -> String {
        self.id.into()
    }
    fn description(&self) -> String {
        "broken on purpose".into()
    }
    fn required_features(&self) -> wgpu::Features {
        if self.id == "test/needs-missing-feature" {
            // A feature the context never asks for, so no adapter's device has it.
            wgpu::Features::SHADER_F64
        } else {
            wgpu::Features::empty()
        }
    }
    fn supports(&self, _: &Scene) -> bool {
        self.id != "test/unsupported"
    }
    fn prepare(&mut self, _: &mut Frame, _: &GpuScene) -> TechniqueResult<()> {
        Ok(())
    }
    fn render(&mut self, _: &mut Frame, _: &GpuScene, _: &View, _: &Target) -> TechniqueResult<()> {
        match self.id {
            "test/panics" => panic!("test technique panics"),
            _ => Err(TechniqueError::Unsupported("test technique fails".into())),
        }
    }
}

fn techniques() -> Vec<Box<dyn Technique>> {
    vec![
        Box::new(Constant {
            id: "test/constant",
            level: 0.25,
            drift: 0.0,
            pace: None,
        }),
        Box::new(Constant {
            id: "test/drifts",
            level: 0.5,
            drift: -0.125,
            pace: None,
        }),
        Box::new(NanImage),
        Box::new(Broken { id: "test/fails" }),
        Box::new(Broken { id: "test/panics" }),
        Box::new(Broken {
            id: "test/needs-missing-feature",
        }),
        Box::new(Broken {
            id: "test/unsupported",
        }),
    ]
}

/// A constant 0.5 image; the left half of the image is "masked". Counts its renders.
struct HalfGrey {
    renders: AtomicUsize,
}

impl GroundTruth for HalfGrey {
    fn key(&self) -> String {
        "half-grey".into()
    }
    fn render(&self, _: &Scene, _: &Camera, _: f32, w: u32, h: u32) -> anyhow::Result<Reference> {
        self.renders.fetch_add(1, Ordering::SeqCst);
        let mut image = HdrImage::new(w, h);
        image
            .pixels
            .iter_mut()
            .for_each(|p| *p = [0.5, 0.5, 0.5, 1.0]);
        let mask = (0..w * h).map(|i| i % w < w / 2).collect();
        Ok(Reference {
            image,
            object_ids: vec![0; (w * h) as usize],
            mask,
            stats: ReferenceStats {
                camera_rays: (w * h) as u64,
                ..Default::default()
            },
        })
    }
}

/// The harness environment of these tests: the test techniques against `truth`.
fn test_env(truth: &HalfGrey) -> Env<'_> {
    Env {
        ctx: testkit::context(),
        techniques: &techniques,
        ground_truth: truth,
        progress: false,
    }
}

fn exists(dir: &Path, rel: &str) -> bool {
    dir.join(rel).is_file()
}

#[test]
fn compare_writes_tables_images_and_caches_the_reference() {
    let truth = HalfGrey {
        renders: AtomicUsize::new(0),
    };
    let env = test_env(&truth);
    let out = out_dir("compare");
    let exec = ExecOptions::new(&out);
    let opts = CompareOptions {
        scenes: vec!["cornell-sphere".into()],
        techniques: None,
        all_variants: false,
        size: SIZE,
        frames: FRAMES,
    };
    let report = harness::compare::run(&env, &opts, &exec).unwrap();
    // The one deliberate panic is caught and listed (the binary then exits with status 4);
    // any other caught panic fails the test.
    assert_eq!(
        report.panics,
        vec!["cornell-sphere / test/panics: panicked: test technique panics".to_string()]
    );
    let row = |id: &str| {
        report
            .rows
            .iter()
            .find(|r| r.technique == id)
            .unwrap_or_else(|| panic!("no row {id}"))
    };

    let c = row("test/constant");
    assert_eq!(c.error, None);
    assert!((c.rmse.unwrap() - 0.25).abs() < 1e-6, "rmse {:?}", c.rmse);
    assert!((c.psnr_db.unwrap() - 12.0412).abs() < 1e-3);
    assert!(c.flip_mean.unwrap() > 0.0 && c.flip_mean_masked.unwrap() > 0.0);
    assert_eq!(c.masked_pixels, Some(32 * 16));
    assert_eq!(c.nan_pixels, Some(0));
    // Every frame on the path is timed; 3 timed frames asked for, no more than the 3 error
    // frames: the row is timed on its error frames (times 0, 1 and 2).
    assert_eq!(c.frames, 3);
    assert!(
        c.frame_ms_median.unwrap() >= 0.0 && c.frame_ms_p95.unwrap() >= c.frame_ms_median.unwrap()
    );
    assert!(
        ["gpu-timestamp", "wall"].contains(&c.timer.as_str()),
        "{}",
        c.timer
    );
    if c.timer == "gpu-timestamp" {
        assert!(c.spans_ms.contains_key("clear_ms"), "{:?}", c.spans_ms);
    }
    assert_eq!(row("test/nan").nan_pixels, Some(32 * 32));
    assert!(
        row("test/nan").psnr_db.unwrap().is_nan(),
        "an image with no finite pixel is no perfect match"
    );
    assert!(
        row("test/fails")
            .error
            .as_deref()
            .unwrap()
            .contains("test technique fails")
    );
    assert!(
        row("test/panics")
            .error
            .as_deref()
            .unwrap()
            .contains("panicked: test technique panics")
    );
    // Error along the camera path: 0.5, 0.375 and 0.25 at times 0, 1 and 2 against 0.5.
    let d = row("test/drifts");
    assert_eq!(d.error_times, vec![0.0, 1.0, 2.0]);
    assert!((d.rmse.unwrap() - 0.125).abs() < 1e-6, "{:?}", d.rmse);
    assert!((d.rmse_worst.unwrap() - 0.25).abs() < 1e-6);
    assert_eq!(d.worst_time, Some(2.0));
    assert!(d.flip_mean_masked_worst.unwrap() > d.flip_mean_masked.unwrap());
    assert!(
        (c.rmse_worst.unwrap() - c.rmse.unwrap()).abs() < 1e-9,
        "a constant error is its own worst"
    );
    assert_eq!(report.rows.len(), 5, "skipped techniques have no rows");
    let skipped: Vec<&str> = report
        .skipped
        .iter()
        .map(|s| s.technique.as_str())
        .collect();
    assert_eq!(skipped, ["test/needs-missing-feature", "test/unsupported"]);
    assert!(
        report.skipped[0].reason.contains("lacks required features"),
        "{}",
        report.skipped[0].reason
    );
    assert_eq!(report.errors.len(), 2);

    for f in [
        "results.csv",
        "results.json",
        "results.md",
        "images/cornell-sphere/reference.png",
        "images/cornell-sphere/reference.exr",
        "images/cornell-sphere/test__constant.png",
        "images/cornell-sphere/test__constant.exr",
        "images/cornell-sphere/test__constant.flip.png",
        "images/cornell-sphere/test__nan.png",
        "images/cornell-sphere/reference.t1.png",
        "images/cornell-sphere/reference.t2.png",
        "images/cornell-sphere/test__drifts.t2.png",
        "images/cornell-sphere/test__drifts.t2.flip.png",
    ] {
        assert!(exists(&out, f), "missing {f}");
    }
    let exr =
        harness::images::read_exr(&out.join("images/cornell-sphere/test__constant.exr")).unwrap();
    assert!(exr.pixels.iter().all(|p| p[..3] == [0.25; 3]));
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert!(csv.starts_with("scene,technique,width,height,frames,frame_ms_median,frame_ms_p95,prepare_ms,timer,rmse,psnr_db,flip_mean,flip_mean_masked,flip_over_0_1_pct,nan_pixels,"));
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .contains(",rmse_worst,flip_mean_worst,flip_mean_masked_worst,worst_time,error_times,")
    );
    assert_eq!(csv.lines().count(), 6);
    let md = std::fs::read_to_string(out.join("results.md")).unwrap();
    assert!(md.starts_with("# Results\n\n- command line: "), "{md}");
    assert!(md.contains("\n| cornell-sphere | test/constant |"), "{md}");
    let wall = std::fs::read_to_string(out.join("wall.md")).unwrap();
    for section in [
        "## By family",
        "## By scene",
        "## Per row",
        "- git commit: ",
    ] {
        assert!(wall.contains(section), "wall.md lacks {section:?}:\n{wall}");
    }
    for row in csv.lines().skip(1) {
        let technique = row.split(',').nth(1).unwrap();
        assert!(
            wall.contains(&format!("| cornell-sphere | {technique} |")),
            "wall.md lacks the row of {technique}:\n{wall}"
        );
    }
    assert!(
        wall.contains("| test | "),
        "wall.md has no line for the family test:\n{wall}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["skipped"].as_array().unwrap().len(), 2);
    assert_eq!(json["references"][0]["cached"], false);
    assert_eq!(
        json["references"][0]["miss"], "no cached reference of this scene",
        "a miss says why"
    );
    assert_eq!(json["references"].as_array().unwrap().len(), 3);
    assert_eq!(json["rows"][1]["errors_at"][2]["time"], 2.0);
    assert_eq!(
        truth.renders.load(Ordering::SeqCst),
        3,
        "one reference per time"
    );
    // The page: written although techniques failed, which it lists; NaN rows marked; the
    // images and HDR copies of every time referenced (the browser test opens such a page).
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains(r#"<section id="failures""#) && page.contains("test technique fails"));
    assert!(page.contains("panic: cornell-sphere / test/panics"));
    assert!(page.contains(r#"class="has-nan""#));
    assert!(
        page.contains("test/needs-missing-feature: "),
        "skipped with the reason"
    );
    assert!(page.contains("<details><summary>Skipped: 2 (scene, technique) pairs"));
    for f in [
        "images/cornell-sphere/test__drifts.t2.flip.png",
        "images/cornell-sphere/test__constant.hdr.js",
        "images/cornell-sphere/reference.t1.hdr.js",
    ] {
        assert!(page.contains(&format!("\"{f}\"")), "the page lacks {f}");
        assert!(exists(&out, f), "missing {f}");
    }
    assert!(
        !page.contains("test__fails.png"),
        "no image of a failed technique"
    );

    // Second run: the reference comes from the cache.
    let opts = CompareOptions {
        techniques: Some(vec!["test/constant".into()]),
        ..opts
    };
    let again = harness::compare::run(&env, &opts, &exec).unwrap();
    assert!(again.panics.is_empty(), "{:?}", again.panics);
    assert_eq!(truth.renders.load(Ordering::SeqCst), 3);
    assert!(again.references[0].cached);
    assert_eq!(again.references[0].miss, None);
    assert_eq!(again.rows.len(), 1);
    assert_eq!(again.rows[0].rmse, c.rmse);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn sweep_over_a_technique_and_a_scene_parameter() {
    let truth = HalfGrey {
        renders: AtomicUsize::new(0),
    };
    let env = test_env(&truth);
    let out = out_dir("sweep");
    let exec = ExecOptions::new(&out);
    let opts = SweepOptions {
        scene: "cornell-sphere".into(),
        technique: "test/constant".into(),
        param: "level".into(),
        values: vec!["0.25".into(), "0.5".into(), "1".into()],
        size: SIZE,
        frames: FRAMES,
    };
    let report = harness::sweep::run(&env, &opts, &exec).unwrap();
    assert!(report.panics.is_empty(), "{:?}", report.panics);
    let rmse: Vec<f64> = report.rows.iter().map(|r| r.rmse.unwrap()).collect();
    assert!(
        (rmse[0] - 0.25).abs() < 1e-6 && rmse[1] == 0.0 && (rmse[2] - 0.5).abs() < 1e-6,
        "{rmse:?}"
    );
    assert_eq!(report.rows[1].psnr_db, Some(f64::INFINITY));
    assert_eq!(
        truth.renders.load(Ordering::SeqCst),
        3,
        "one reference per error time for a technique parameter"
    );
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(csv.starts_with("scene,technique,param,value,width"));
    assert!(
        csv.contains("cornell-sphere,test/constant,level,0.5,32,32,3,") && csv.contains(",inf,"),
        "{csv}"
    );
    assert!(
        exists(&out, "sweep.svg")
            && exists(&out, "sweep.json")
            && exists(&out, "images/reference.png")
    );
    assert!(exists(&out, "images/test__constant__level=0.5.flip.png"));
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert_eq!(
        page.matches(r#"<svg xmlns="http://www.w3.org/2000/svg" class="plot""#)
            .count(),
        4,
        "FLIP, masked FLIP, RMSE and frame time against the value"
    );
    assert!(page.contains(r#""images/test__constant__level=0.5.hdr.js""#));
    assert!(page.contains(r#""images/reference.png""#));

    // A scene parameter: the spec is rebuilt per value, one reference each.
    let opts = SweepOptions {
        param: "material".into(),
        values: vec!["mirror".into(), "gold".into()],
        ..opts
    };
    let report = harness::sweep::run(&env, &opts, &exec).unwrap();
    assert!(report.panics.is_empty(), "{:?}", report.panics);
    let scenes: Vec<&str> = report.rows.iter().map(|r| r.scene.as_str()).collect();
    assert_eq!(
        scenes,
        [
            "cornell-sphere:material=mirror",
            "cornell-sphere:material=gold"
        ]
    );
    assert_eq!(truth.renders.load(Ordering::SeqCst), 9);
    assert!(exists(&out, "images/reference__material=gold.png"));
    assert!(exists(&out, "images/reference__material=gold.t1.png"));
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains(r#""images/reference__material=gold.t1.png""#));
    assert!(
        page.contains("reference, material=gold"),
        "a reference per value"
    );

    // Bad parameters fail before any GPU work, with one sentence.
    let bad = |param: &str, values: &[&str]| {
        let o = SweepOptions {
            param: param.into(),
            values: values.iter().map(|v| v.to_string()).collect(),
            ..opts.clone()
        };
        format!("{:#}", harness::sweep::run(&env, &o, &exec).unwrap_err())
    };
    assert!(bad("nosuch", &["1"]).contains("has a parameter \"nosuch\""));
    assert!(bad("level", &["9"]).contains("outside its range"));
    assert!(bad("level", &["x"]).contains("not a number"));
    assert!(bad("material", &["plastic"]).contains("unknown material"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_interleaves_and_states_ratios_with_their_spread() {
    let truth = HalfGrey {
        renders: AtomicUsize::new(0),
    };
    let env = test_env(&truth);
    let out = out_dir("bench");
    let opts = harness::bench::BenchOptions {
        scene: "cornell-sphere".into(),
        techniques: vec!["test/constant".into(), "test/constant:level=0.5".into()],
        span: "frame".into(),
        size: SIZE,
        time: 1.0,
        rounds: 3,
        frames: 2,
        warmup: 1,
        out: Some(out.clone()),
    };
    let report = harness::bench::run(&env, &opts).unwrap();
    assert_eq!(report.rows.len(), 2);
    assert_eq!(report.rows[0].verdict, "baseline");
    assert_eq!(report.rows[0].round_medians_ms.len(), 3);
    assert!((report.rows[0].ratio_median - 1.0).abs() < 1e-12);
    let r = &report.rows[1];
    assert!(r.ratio_min <= r.ratio_median && r.ratio_median <= r.ratio_max && r.ratio_min > 0.0);
    assert_eq!(
        truth.renders.load(Ordering::SeqCst),
        0,
        "bench renders no reference"
    );
    assert!(exists(&out, "bench.json") && exists(&out, "bench.md"));
    assert!(report.markdown.contains("| test/constant:level=0.5 |"));

    let bad = |techniques: &[&str], span: &str| {
        let o = harness::bench::BenchOptions {
            techniques: techniques.iter().map(|t| t.to_string()).collect(),
            span: span.into(),
            out: None,
            ..opts.clone()
        };
        format!("{:#}", harness::bench::run(&env, &o).unwrap_err())
    };
    assert!(bad(&["test/constant"], "frame").contains("at least two techniques"));
    assert!(bad(&["test/constant", "nope"], "frame").contains("unknown technique \"nope\""));
    assert!(
        bad(&["test/constant", "test/constant:level=9"], "frame").contains("outside its range")
    );
    assert!(bad(&["test/constant", "test/unsupported"], "frame").contains("does not support"));
    assert!(bad(&["test/constant", "test/nan"], "no-such-span").contains("recorded no span"));
    // The constant records a "clear" span, the NaN image none.
    assert!(bad(&["test/constant", "test/nan"], "clear").contains("test/nan recorded no span"));
    let _ = std::fs::remove_dir_all(&out);
}

/// The columns of results.csv that are timings (or made from them): a sharded run and its
/// merge, or a resumed run, equal the unsharded or uninterrupted run in every other.
const TIMING_COLUMNS: &[&str] = &[
    "frame_ms_median",
    "frame_ms_p95",
    "prepare_ms",
    "speedup_vs_raytracer",
    "wall_prepare_s",
    "wall_frames_s",
    "wall_metrics_s",
    "wall_write_s",
];

/// results.csv without its timing columns.
fn figures_of(csv: &str) -> Vec<Vec<String>> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !TIMING_COLUMNS.contains(&header[i]))
        .collect();
    std::iter::once(header.iter().map(|s| s.to_string()).collect::<Vec<_>>())
        .chain(lines.map(|l| l.split(',').map(String::from).collect()))
        .map(|cells: Vec<String>| keep.iter().filter_map(|&i| cells.get(i).cloned()).collect())
        .collect()
}

fn merge_options() -> CompareOptions {
    CompareOptions {
        scenes: vec!["cornell-sphere".into(), "cornell-box".into()],
        techniques: Some(vec![
            "test/constant".into(),
            "test/drifts".into(),
            "test/nan".into(),
            "test/fails".into(),
            "test/unsupported".into(),
        ]),
        all_variants: false,
        size: SIZE,
        frames: FRAMES,
    }
}

#[test]
fn shards_merge_into_the_unsharded_run() {
    let truth = HalfGrey {
        renders: AtomicUsize::new(0),
    };
    let env = test_env(&truth);
    let opts = merge_options();
    let whole_dir = out_dir("whole");
    let whole = harness::compare::run(&env, &opts, &ExecOptions::new(&whole_dir)).unwrap();
    assert_eq!(whole.rows.len(), 8, "4 techniques on 2 scenes");
    let mut shards = Vec::new();
    for index in 1..=3 {
        let dir = out_dir(&format!("shard-{index}"));
        let exec = ExecOptions {
            shard: Some(harness::plan::Shard { index, count: 3 }),
            ..ExecOptions::new(&dir)
        };
        let part = harness::compare::run(&env, &opts, &exec).unwrap();
        assert!(part.rows.len() < 8 && dir.join("index.html").is_file());
        assert!(
            dir.join("results.csv").is_file(),
            "a shard is a whole output folder"
        );
        shards.push(dir);
    }
    // Out of order on purpose: merge orders the shards.
    shards.swap(0, 2);
    let merged_dir = out_dir("merged");
    let merged = harness::merge::merge(&shards, &merged_dir).unwrap();
    assert_eq!(merged.shard, None);
    let read = |dir: &Path| std::fs::read_to_string(dir.join("results.csv")).unwrap();
    assert_eq!(
        figures_of(&read(&merged_dir)),
        figures_of(&read(&whole_dir)),
        "the merge is the unsharded run, timings aside"
    );
    assert_eq!(merged.skipped, whole.skipped);
    assert_eq!(merged.errors, whole.errors);
    let files = |r: &harness::model::RunReport| -> Vec<String> {
        r.images
            .iter()
            .flat_map(|w| w.frames.iter().map(|f| f.png.clone()))
            .collect()
    };
    assert_eq!(files(&merged), files(&whole));
    for f in files(&merged) {
        assert!(exists(&merged_dir, &f), "the merge has {f}");
    }
    let page = std::fs::read_to_string(merged_dir.join("index.html")).unwrap();
    assert!(
        page.contains("8 results"),
        "the merged page shows every row"
    );

    // Not a complete set, or shards of another plan: refused with one sentence.
    let err = harness::merge::merge(&shards[..2], &out_dir("partial")).unwrap_err();
    assert!(
        format!("{err:#}").contains("merge needs each of 1..=3 once"),
        "{err:#}"
    );
    let mut other = shards.clone();
    other[0] = whole_dir.clone();
    let err = harness::merge::merge(&other, &out_dir("mixed")).unwrap_err();
    assert!(
        format!("{err:#}").contains("not a shard") || format!("{err:#}").contains("another plan"),
        "{err:#}"
    );
    for d in shards.iter().chain([&whole_dir, &merged_dir]) {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn a_resumed_run_keeps_the_finished_rows_and_runs_the_rest() {
    let truth = HalfGrey {
        renders: AtomicUsize::new(0),
    };
    let env = test_env(&truth);
    let opts = merge_options();
    let dir = out_dir("resume");
    let full = harness::compare::run(&env, &opts, &ExecOptions::new(&dir)).unwrap();
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    // As a run stopped after its fifth row leaves the folder: the tables hold five rows.
    let mut stopped = full.clone();
    stopped.rows.truncate(5);
    stopped.images.retain(|w| {
        w.technique.is_none()
            || stopped
                .rows
                .iter()
                .any(|r| Some(&r.technique) == w.technique.as_ref() && r.scene == w.scene)
    });
    std::fs::write(
        dir.join("results.json"),
        serde_json::to_string(&stopped).unwrap(),
    )
    .unwrap();
    let exec = ExecOptions {
        resume: true,
        ..ExecOptions::new(&dir)
    };
    let resumed = harness::compare::run(&env, &opts, &exec).unwrap();
    assert_eq!(resumed.rows.len(), 8);
    assert_eq!(
        figures_of(&std::fs::read_to_string(dir.join("results.csv")).unwrap()),
        figures_of(&csv),
        "the resumed run's table is the uninterrupted run's"
    );
    // The first five rows kept their own timings and wall clocks: they were not run again.
    for (a, b) in resumed.rows.iter().zip(&full.rows).take(5) {
        assert_eq!(
            (a.frame_ms_median, a.wall),
            (b.frame_ms_median, b.wall),
            "{} kept",
            a.technique
        );
    }
    // Another plan in the folder is refused.
    let other = CompareOptions {
        size: Size::new(16, 16),
        ..opts
    };
    let err = harness::compare::run(&env, &other, &exec).unwrap_err();
    assert!(
        format!("{err:#}").contains("results of another run"),
        "{err:#}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A row the timed budget leaves its error frames alone renders each of them once: the
/// warm-up frame is the first (timed, its image read back), so nothing is rendered twice. A
/// row within its budget keeps its warm-up frame apart from the timed frames.
#[test]
fn a_row_timed_on_its_error_frames_renders_each_once() {
    let ctx = testkit::context();
    let scene = scene::load("cornell-sphere").unwrap();
    let mut gpu_scene = GpuScene::new(ctx, &scene).unwrap();
    let run = |budget_s: f64, gpu_scene: &mut GpuScene| {
        let renders = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        // Level 0.25 * time: each error frame's image says which time it shows.
        let mut slow = Constant {
            id: "test/slow",
            level: 0.0,
            drift: 0.25,
            pace: Some(Pace {
                sleep: std::time::Duration::from_millis(20),
                renders: renders.clone(),
            }),
        };
        let frames = Frames {
            timed: 8,
            warmup: 1,
            errors: 3,
            timed_budget_s: budget_s,
        };
        let run = harness::measure::run_technique(
            ctx,
            &mut slow,
            gpu_scene,
            SIZE,
            frames,
            &mut |_, _, _| {},
        )
        .unwrap();
        let renders = renders.lock().unwrap().clone();
        (run, renders)
    };

    // 20 ms a frame against 10 ms of budget: error frames alone, each rendered once.
    let (slow_run, renders) = run(0.01, &mut gpu_scene);
    assert_eq!(renders, [0.0, 1.0, 2.0]);
    assert_eq!(slow_run.frame.samples, 3);
    let levels: Vec<(f32, f32)> = slow_run
        .error_frames
        .iter()
        .map(|f| (f.time, f.image.pixels[0][0]))
        .collect();
    assert_eq!(levels, [(0.0, 0.0), (1.0, 0.25), (2.0, 0.5)]);

    // No budget: the warm-up frame, then 8 timed frames of which 0 and 1 are error frames,
    // then the error frame at 2.
    let (run, renders) = run(0.0, &mut gpu_scene);
    assert_eq!(
        renders,
        [0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0]
    );
    assert_eq!(run.frame.samples, 9);
    assert_eq!(run.error_frames.len(), 3);
}
