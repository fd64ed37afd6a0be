//! The HTML report in a real browser: `compare` on two small scenes (real techniques, the
//! exact tracer, and one that fails on purpose), then `index.html` opened in headless Chromium
//! from the file system and driven over the DevTools protocol (`--remote-debugging-pipe`):
//!
//! - the page loads with no console error, exception or failed load;
//! - every image and HDR copy it references exists, and every image decoded;
//! - a drag of the comparison slider's handle (real mouse events) moves the split;
//! - the exposure control redraws from the HDR copy: at 0 EV the canvas equals the PNG the run
//!   wrote (within the RGBE copy's quantisation), at +3 EV it is brighter;
//! - sorting and filtering the table work, and every cell's number is results.csv's;
//! - a screenshot is taken and is not blank (saved beside the report).
//!
//! Chromium comes from the project's setup (`cargo xtask test` installs Debian's `chromium`
//! and sets `HARNESS_BROWSER_TEST=require`, which makes a missing browser a failure); run
//! elsewhere without one, the test says so and passes. `HARNESS_CHROMIUM` names another binary.

use harness::compare::CompareOptions;
use harness::{CpuReference, Env, Frames, Size};
use scene::{Frame, GpuScene, Scene, Technique, TechniqueError, TechniqueResult, View};
use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

/// Fails in every frame (the page must list it and still be written).
struct Fails;

impl Technique for Fails {
    fn id(&self) -> String {
        "test/fails".into()
    }
    fn description(&self) -> String {
        "fails on purpose".into()
    }
    fn supports(&self, _: &Scene) -> bool {
        true
    }
    fn prepare(&mut self, _: &mut Frame, _: &GpuScene) -> TechniqueResult<()> {
        Ok(())
    }
    fn render(
        &mut self,
        _: &mut Frame,
        _: &GpuScene,
        _: &View,
        _: &gpu::Target,
    ) -> TechniqueResult<()> {
        Err(TechniqueError::Unsupported("test technique fails".into()))
    }
}

const TECHNIQUES: &[&str] = &["raster", "envmap/classic", "raytracer/caustics"];

fn techniques() -> Vec<Box<dyn Technique>> {
    let mut chosen: Vec<Box<dyn Technique>> = harness::registry()
        .into_iter()
        .filter(|t| TECHNIQUES.contains(&t.id().as_str()))
        .collect();
    chosen.push(Box::new(Fails));
    chosen
}

fn find_chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("HARNESS_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome", "chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|p| p.is_file())
}

/// Chromium driven over the DevTools protocol on a pipe: our writes arrive on its fd 3, its
/// replies come from its fd 4, each message JSON ended by a NUL byte.
struct Browser {
    child: Child,
    to: ChildStdin,
    from: BufReader<ChildStdout>,
    next_id: u64,
    session: Option<String>,
    /// Every event received so far (console messages, exceptions, log entries).
    events: Vec<Value>,
}

impl Browser {
    fn launch(chromium: &Path, profile: &Path) -> Browser {
        // The shell hands our stdin/stdout pipes to Chromium as fds 3 and 4.
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(r#"exec "$0" "$@" 3<&0 4>&1 0</dev/null 1>/dev/null"#)
            .arg(chromium)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--no-default-browser-check",
                "--disable-extensions",
                "--hide-scrollbars",
                "--remote-debugging-pipe",
                "--window-size=1400,1000",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromium");
        let to = child.stdin.take().unwrap();
        let from = BufReader::new(child.stdout.take().unwrap());
        Browser {
            child,
            to,
            from,
            next_id: 1,
            session: None,
            events: Vec::new(),
        }
    }

    /// Sends a command (to the page's session once attached) and waits for its result.
    fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        let mut message = json!({ "id": id, "method": method, "params": params });
        if let Some(session) = &self.session {
            message["sessionId"] = json!(session);
        }
        let mut bytes = serde_json::to_vec(&message).unwrap();
        bytes.push(0);
        self.to.write_all(&bytes).expect("write to chromium");
        self.to.flush().unwrap();
        loop {
            let mut buffer = Vec::new();
            let n = self
                .from
                .read_until(0, &mut buffer)
                .expect("read from chromium");
            assert!(n > 0, "chromium closed the pipe waiting for {method}");
            buffer.pop();
            let reply: Value = serde_json::from_slice(&buffer).expect("a JSON message");
            if reply["id"] == json!(id) {
                if let Some(error) = reply.get("error") {
                    panic!("{method} failed: {error}");
                }
                return reply["result"].clone();
            }
            if reply.get("method").is_some() {
                self.events.push(reply);
            }
        }
    }

    /// Evaluates an expression in the page (awaiting a promise) and returns its JSON value.
    fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        if let Some(exception) = result.get("exceptionDetails") {
            panic!("{expression} threw: {exception}");
        }
        result["result"]["value"].clone()
    }

    fn mouse(&mut self, kind: &str, x: f64, y: f64) {
        self.call(
            "Input.dispatchMouseEvent",
            json!({ "type": kind, "x": x, "y": y, "button": "left", "buttons": 1, "clickCount": 1 }),
        );
    }

    /// Waits until `expression` is true in the page.
    fn wait_for(&mut self, expression: &str, what: &str) {
        let start = Instant::now();
        while self.eval(expression) != json!(true) {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "timed out waiting for {what}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Console errors, uncaught exceptions and failed loads among the events so far.
    fn errors(&self) -> Vec<String> {
        self.events
            .iter()
            .filter(|e| {
                let p = &e["params"];
                match e["method"].as_str() {
                    Some("Runtime.exceptionThrown") => true,
                    Some("Runtime.consoleAPICalled") => {
                        matches!(p["type"].as_str(), Some("error" | "assert"))
                    }
                    Some("Log.entryAdded") => p["entry"]["level"] == json!("error"),
                    _ => false,
                }
            })
            .map(|e| e.to_string())
            .collect()
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn decode_base64(text: &str) -> Vec<u8> {
    data_encoding::BASE64
        .decode(text.as_bytes())
        .expect("base64")
}

/// results.csv as a header and rows of fields (RFC 4180 quoting).
fn read_csv(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut records = Vec::new();
    let (mut record, mut field, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => record.push(std::mem::take(&mut field)),
            ('\n', false) => {
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (c, _) => field.push(c),
        }
    }
    let header = records.remove(0);
    (header, records)
}

#[test]
fn the_report_works_in_headless_chromium() {
    let required = std::env::var("HARNESS_BROWSER_TEST").is_ok_and(|v| v == "require");
    let Some(chromium) = find_chromium() else {
        assert!(
            !required,
            "HARNESS_BROWSER_TEST=require but no Chromium found (install Debian's chromium, or \
             set HARNESS_CHROMIUM)"
        );
        eprintln!("skipped: no Chromium here (`cargo xtask test` installs it)");
        return;
    };
    let out = std::env::temp_dir().join(format!("harness-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let reference = CpuReference::fixed(truth::reference::ReferenceOptions {
        photons: 200_000,
        ..Default::default()
    });
    let env = Env {
        ctx: testkit::context(),
        techniques: &techniques,
        ground_truth: &reference,
        progress: false,
    };
    let opts = CompareOptions {
        scenes: vec!["cornell-sphere".into(), "hu-qin".into()],
        techniques: None,
        all_variants: true,
        size: Size::new(64, 64),
        frames: Frames {
            timed: 2,
            warmup: 1,
            errors: 2,
            timed_budget_s: 0.0,
        },
    };
    let report = harness::compare::run(&env, &opts, &harness::engine::ExecOptions::new(&out))
        .expect("compare runs");
    assert!(
        report.errors.iter().any(|e| e.contains("test/fails")),
        "{:?}",
        report.errors
    );
    let page = out.join("index.html");
    assert!(page.is_file(), "compare writes index.html");

    let profile = out.join("chromium-profile");
    let mut browser = Browser::launch(&chromium, &profile);
    let target = browser.call("Target.createTarget", json!({ "url": "about:blank" }));
    let attached = browser.call(
        "Target.attachToTarget",
        json!({ "targetId": target["targetId"], "flatten": true }),
    );
    browser.session = attached["sessionId"].as_str().map(String::from);
    for domain in ["Runtime.enable", "Log.enable", "Page.enable"] {
        browser.call(domain, json!({}));
    }
    browser.call(
        "Emulation.setDeviceMetricsOverride",
        json!({ "width": 1400, "height": 1000, "deviceScaleFactor": 1, "mobile": false }),
    );
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    browser.call("Page.navigate", json!({ "url": url }));
    browser.wait_for(
        "document.readyState === 'complete' && document.body.dataset.ready === '1'",
        "the page to draw",
    );
    browser.wait_for(
        "Array.from(document.images).every(i => i.complete)",
        "the images to load",
    );

    // Every referenced file exists, and every image decoded.
    let referenced = browser.eval(
        "(() => { const d = JSON.parse(document.getElementById('report-data').textContent); \
         const files = []; for (const g of d.groups) for (const e of g.entries) for (const f of e.frames) \
         files.push(f.png, f.flip, f.hdr); \
         return files.concat(Array.from(document.images).map(i => i.getAttribute('src'))).filter(f => f); })()",
    );
    let referenced: Vec<String> = serde_json::from_value(referenced).unwrap();
    assert!(referenced.len() > 20, "{referenced:?}");
    for file in &referenced {
        assert!(
            out.join(file).is_file(),
            "the page references {file}, absent"
        );
    }
    for kind in [".png", ".flip.png", ".hdr.js"] {
        assert!(
            referenced.iter().any(|f| f.ends_with(kind)),
            "no {kind} file"
        );
    }
    // Complete: every entry that ran has an image at every error time of its scene, every
    // technique a FLIP map and an HDR copy there (the page lists what the run wrote, so a wrong
    // path or a lost time would show here as a missing frame).
    let incomplete = browser.eval(
        "(() => { const d = JSON.parse(document.getElementById('report-data').textContent); \
         const bad = []; for (const g of d.groups) { \
           if (g.times.length !== 2) bad.push(g.title + ': times ' + g.times); \
           for (const e of g.entries) { if (e.error) continue; \
             if (e.frames.length !== g.times.length) bad.push(g.title + ' / ' + e.id + ': ' + e.frames.length + ' frames'); \
             for (const f of e.frames) if (!f.hdr || (e.reference !== null && e.id !== 'reference' && !f.flip)) \
               bad.push(g.title + ' / ' + e.id + ' at ' + f.time + ': no FLIP map or HDR copy'); } } \
         return bad; })()",
    );
    assert_eq!(incomplete, json!([]), "entries missing frames");
    let broken = browser.eval(
        "Array.from(document.images).filter(i => i.getAttribute('src') && !i.naturalWidth).map(i => i.getAttribute('src'))",
    );
    assert_eq!(broken, json!([]), "images that did not decode");

    // The failure is listed; the grid shows each scene's reference and techniques.
    let failures = browser.eval("document.getElementById('failures').innerText");
    assert!(
        failures.as_str().unwrap().contains("test/fails"),
        "{failures}"
    );
    let cards = browser.eval("document.querySelectorAll('section.group .card').length");
    assert_eq!(cards, json!(2 * (1 + TECHNIQUES.len() + 1)));
    let plots = browser.eval("document.querySelectorAll('section.group svg.plot').length");
    assert_eq!(plots, json!(2), "a Pareto plot per scene");

    // A drag of the slider's handle moves the split.
    let handle = browser.eval(
        "(() => { const s = document.querySelector('section.group .stage'); \
         s.scrollIntoView(); const h = s.querySelector('.handle').getBoundingClientRect(); \
         const r = s.getBoundingClientRect(); \
         return [h.left + h.width / 2, h.top + h.height / 2, r.left, r.width, Number(s.dataset.split)]; })()",
    );
    let [hx, hy, left, width, before] = serde_json::from_value::<[f64; 5]>(handle).unwrap();
    assert_eq!(before, 0.5);
    browser.mouse("mousePressed", hx, hy);
    for step in 1..=5 {
        let x = hx + (left + 0.2 * width - hx) * step as f64 / 5.0;
        browser.mouse("mouseMoved", x, hy);
    }
    browser.mouse("mouseReleased", left + 0.2 * width, hy);
    let split =
        browser.eval("Number(document.querySelector('section.group .stage').dataset.split)");
    let split = split.as_f64().unwrap();
    assert!(
        (split - 0.2).abs() < 0.02,
        "the drag left the split at {split}"
    );
    let clip =
        browser.eval("document.querySelector('section.group .stage canvas.b').style.clipPath");
    assert!(clip.as_str().unwrap().contains("20"), "{clip}");

    // Exposure: at 0 EV canvas A (the default: the first technique) equals its PNG within the
    // RGBE copy's quantisation; at +3 EV it is brighter.
    let canvas_a = "(() => { const c = document.querySelector('section.group .stage canvas.a'); \
         return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data); })()";
    let shown: Vec<u8> = serde_json::from_value(browser.eval(canvas_a)).unwrap();
    let label =
        browser.eval("document.querySelector('section.group .pick-a').selectedOptions[0].text");
    let scene_dir = &report.image_dirs["cornell-sphere"];
    let png = image::open(out.join("images").join(scene_dir).join(format!(
        "{}.png",
        harness::file_name(label.as_str().unwrap())
    )))
    .unwrap()
    .into_rgb8();
    assert_eq!(
        shown.len(),
        4 * png.width() as usize * png.height() as usize
    );
    let worst = png
        .pixels()
        .zip(shown.chunks(4))
        .flat_map(|(p, s)| (0..3).map(move |c| (p[c] as i32 - s[c] as i32).abs()))
        .max()
        .unwrap();
    assert!(
        worst <= 3,
        "the HDR copy at 0 EV is {worst} levels off the PNG"
    );
    let renders = browser.eval("Number(document.querySelector('section.group').dataset.renders)");
    browser.eval(
        "(() => { const e = document.querySelector('section.group .exposure'); e.value = 3; \
         e.dispatchEvent(new Event('input')); })()",
    );
    browser.wait_for(
        &format!("Number(document.querySelector('section.group').dataset.renders) > {renders}"),
        "the redraw at +3 EV",
    );
    let brighter: Vec<u8> = serde_json::from_value(browser.eval(canvas_a)).unwrap();
    let sum = |v: &[u8]| v.iter().map(|&b| b as u64).sum::<u64>();
    assert!(
        sum(&brighter) > sum(&shown) + shown.len() as u64,
        "+3 EV is not brighter"
    );

    // The table: sorting by frame time orders the rows; a family filter hides the others; and
    // every cell holds results.csv's text.
    let sorted = browser.eval(
        "(() => { const th = document.querySelector('th[data-col=frame_ms_median]'); th.click(); \
         const col = th.cellIndex; \
         return Array.from(document.querySelectorAll('#results-table tbody tr')) \
           .map(r => r.cells[col].dataset.v).filter(v => v !== '').map(Number); })()",
    );
    let sorted: Vec<f64> = serde_json::from_value(sorted).unwrap();
    assert!(sorted.windows(2).all(|w| w[0] <= w[1]), "{sorted:?}");
    let shown_rows = browser.eval(
        "(() => { const f = document.getElementById('filter-family'); f.value = 'raytracer'; \
         f.dispatchEvent(new Event('change')); \
         return Array.from(document.querySelectorAll('#results-table tbody tr')).filter(r => !r.hidden).length; })()",
    );
    assert_eq!(shown_rows, json!(2), "one raytracer row per scene");
    let table = browser.eval(
        "(() => { const cols = Array.from(document.querySelectorAll('#results-table th')).map(h => h.dataset.col); \
         return Array.from(document.querySelectorAll('#results-table tbody tr')).map(r => { \
           const o = {}; cols.forEach((c, i) => o[c] = [r.cells[i].dataset.v, r.cells[i].textContent]); return o; }); })()",
    );
    let table: Vec<std::collections::BTreeMap<String, (String, String)>> =
        serde_json::from_value(table).unwrap();
    let (header, records) = read_csv(&std::fs::read_to_string(out.join("results.csv")).unwrap());
    assert_eq!(table.len(), records.len());
    let key = |scene: &str, technique: &str| format!("{scene} / {technique}");
    let mut compared = 0;
    for record in &records {
        let field = |name: &str| &record[header.iter().position(|h| h == name).unwrap()];
        let row = table
            .iter()
            .find(|r| {
                key(&r["scene"].0, &r["technique"].0) == key(field("scene"), field("technique"))
            })
            .unwrap_or_else(|| {
                panic!(
                    "no table row for {}",
                    key(field("scene"), field("technique"))
                )
            });
        for (column, (value, text)) in row {
            assert_eq!(
                value,
                field(column),
                "{column} of {}",
                key(field("scene"), field("technique"))
            );
            if let Ok(v) = value
                .parse::<f64>()
                .map_err(|_| ())
                .and_then(|v| v.is_finite().then_some(v).ok_or(()))
            {
                let shown: f64 = text.parse().unwrap_or_else(|_| panic!("{column}: {text}"));
                assert!(
                    (shown - v).abs() <= 5e-4 * v.abs().max(1e-300),
                    "{column}: shown {text}, CSV {value}"
                );
            }
            compared += 1;
        }
    }
    assert!(compared > 100, "{compared} cells compared");

    // A screenshot, not blank: many colours, and the images' region is not the background.
    browser.eval("window.scrollTo(0, 0)");
    let shot = browser.call("Page.captureScreenshot", json!({ "format": "png" }));
    let bytes = decode_base64(shot["data"].as_str().unwrap());
    std::fs::write(out.join("screenshot.png"), &bytes).unwrap();
    let shot = image::load_from_memory(&bytes).unwrap().into_rgb8();
    let colours: std::collections::HashSet<[u8; 3]> = shot.pixels().map(|p| p.0).collect();
    assert!(
        colours.len() > 200,
        "a blank screenshot ({} colours)",
        colours.len()
    );

    let errors = browser.errors();
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    drop(browser);
    // HARNESS_REPORT_KEEP=1 keeps the report and its screenshot to look at.
    if std::env::var_os("HARNESS_REPORT_KEEP").is_some() {
        eprintln!("report and screenshot in {}", out.display());
    } else {
        let _ = std::fs::remove_dir_all(&out);
    }
}
