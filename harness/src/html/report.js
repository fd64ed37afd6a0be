// The harness report's script (inlined into index.html; no library, nothing fetched).
//
// It reads the JSON block `report-data` (groups: a scene of `compare`, or the values of a
// `sweep`; each with its error-frame times and entries: the reference and the techniques, each
// with its PNG, FLIP map and HDR copy per time) and builds, per group, the image grid and the
// comparison view, then makes the results table sortable and filterable. When everything drawn
// at load is on screen it sets `document.body.dataset.ready` (the browser test waits for it).
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("report-data").textContent);

  // ---- HDR copies -------------------------------------------------------------------------
  // `*.hdr.js` calls harnessHdr(width, height, base64): zlib-compressed RGBE planes. A page
  // opened from the file system may run such scripts but may not read its images' pixels.
  const hdrLoads = new Map();
  const hdrWaiting = new Map();
  window.harnessHdr = function (width, height, base64) {
    const src = document.currentScript && document.currentScript.getAttribute("src");
    const waiting = hdrWaiting.get(src);
    if (!waiting) return;
    hdrWaiting.delete(src);
    decodeHdr(width, height, base64).then(waiting.resolve, waiting.reject);
  };

  function loadHdr(src) {
    if (!hdrLoads.has(src)) {
      hdrLoads.set(src, new Promise((resolve, reject) => {
        hdrWaiting.set(src, { resolve, reject });
        const script = document.createElement("script");
        script.src = src;
        // harnessHdr runs while the script executes, before its load event.
        script.onload = () => {
          if (hdrWaiting.delete(src)) reject(new Error(src + " is not an HDR copy"));
        };
        script.onerror = () => {
          hdrWaiting.delete(src);
          reject(new Error("cannot load " + src));
        };
        document.head.appendChild(script);
      }));
    }
    return hdrLoads.get(src);
  }

  async function decodeHdr(width, height, base64) {
    const text = atob(base64);
    const bytes = new Uint8Array(text.length);
    for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    const planes = new Uint8Array(await new Response(stream).arrayBuffer());
    const n = width * height;
    if (planes.length !== 4 * n) throw new Error("HDR copy of the wrong size");
    const rgb = new Float32Array(3 * n);
    const nonFinite = new Uint8Array(n);
    for (let i = 0; i < n; i++) {
      const e = planes[3 * n + i];
      if (e === 0) {
        // Black, or the marker of a NaN/infinite pixel (magenta with a zero exponent).
        nonFinite[i] = planes[i] === 255 && planes[n + i] === 0 && planes[2 * n + i] === 255;
        continue;
      }
      const scale = Math.pow(2, e - 136);
      rgb[3 * i] = (planes[i] + 0.5) * scale;
      rgb[3 * i + 1] = (planes[n + i] + 0.5) * scale;
      rgb[3 * i + 2] = (planes[2 * n + i] + 0.5) * scale;
    }
    return { width, height, rgb, nonFinite };
  }

  // The PNGs' transfer: clamp to [0, 1], sRGB, round (truth::metrics::channel_to_srgb8).
  function srgb8(v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    const s = v <= 0.0031308 ? v * 12.92 : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
    return Math.floor(s * 255 + 0.5);
  }

  function drawHdr(canvas, hdr, exposure) {
    canvas.width = hdr.width;
    canvas.height = hdr.height;
    const context = canvas.getContext("2d");
    const pixels = context.createImageData(hdr.width, hdr.height);
    const k = Math.pow(2, exposure);
    const out = pixels.data;
    for (let i = 0, n = hdr.width * hdr.height; i < n; i++) {
      if (hdr.nonFinite[i]) {
        out.set([255, 0, 255, 255], 4 * i);
        continue;
      }
      out[4 * i] = srgb8(hdr.rgb[3 * i] * k);
      out[4 * i + 1] = srgb8(hdr.rgb[3 * i + 1] * k);
      out[4 * i + 2] = srgb8(hdr.rgb[3 * i + 2] * k);
      out[4 * i + 3] = 255;
    }
    context.putImageData(pixels, 0, 0);
  }

  const imageLoads = new Map();
  function loadImage(src) {
    if (!imageLoads.has(src)) {
      imageLoads.set(src, new Promise((resolve, reject) => {
        const image = new Image();
        image.onload = () => resolve(image);
        image.onerror = () => reject(new Error("cannot load " + src));
        image.src = src;
      }));
    }
    return imageLoads.get(src);
  }

  function drawImage(canvas, image) {
    canvas.width = image.naturalWidth;
    canvas.height = image.naturalHeight;
    canvas.getContext("2d").drawImage(image, 0, 0);
  }

  // ---- small helpers ----------------------------------------------------------------------
  function element(tag, attributes, ...children) {
    const node = document.createElement(tag);
    for (const [key, value] of Object.entries(attributes || {})) {
      if (key === "class") node.className = value;
      else if (key.startsWith("on")) node.addEventListener(key.slice(2), value);
      else node.setAttribute(key, value);
    }
    for (const child of children) {
      if (child !== null && child !== undefined) {
        node.append(child instanceof Node ? child : document.createTextNode(String(child)));
      }
    }
    return node;
  }

  function short(v) {
    if (v === null || v === undefined) return "–";
    if (!isFinite(v)) return String(v);
    return String(Number(v.toPrecision(4)));
  }

  function speedup(v) {
    if (v === null || v === undefined) return null;
    return (v >= 100 ? v.toFixed(0) : v >= 10 ? v.toFixed(1) : v.toFixed(2)) + "x";
  }

  // The figures under an image: masked FLIP (or FLIP), PSNR, frame time, speed-up.
  function figureLine(f) {
    const line = element("span", { class: "figs" });
    const add = (label, value, unit) => {
      if (value === null || value === undefined) return;
      if (line.childNodes.length) line.append(" · ");
      line.append(label, element("b", {}, value), unit || "");
    };
    if (f.flip_masked !== null) add("FLIP masked ", short(f.flip_masked));
    else add("FLIP ", short(f.flip));
    add("PSNR ", f.psnr_db === null ? null : f.psnr_db >= 999 ? "inf" : f.psnr_db.toFixed(2), " dB");
    add("", f.frame_ms === null ? null : short(f.frame_ms), " ms" + (f.timer === "cpu" ? " (CPU)" : ""));
    add("", speedup(f.speedup), " vs tracer");
    if (f.nan_pixels) {
      line.append(" · ", element("b", { class: "err" }, f.nan_pixels + " NaN px"));
    }
    return line;
  }

  // ---- one group: grid and comparison ------------------------------------------------------
  function setupGroup(section, group) {
    const state = {
      time: 0,
      a: 0,
      b: 0,
      mode: "slider",
      show: "image",
      exposure: 0,
      zoom: 8,
      split: 0.5,
      showingB: false,
      crop: null,
    };
    // Default comparison: the first technique that ran (not the `reference` technique, which
    // is the ground truth itself), against its reference.
    const first = group.entries.findIndex(
      (e) => e.reference !== null && e.id !== "reference" && e.frames.length
    );
    if (first >= 0) {
      state.a = first;
      state.b = group.entries[first].reference;
    }
    const frameOf = (entry) =>
      entry.frames.find((f) => f.time === group.times[state.time]) || null;

    // Time control (only when the path has several error frames).
    const controls = section.querySelector(".group-controls");
    if (group.times.length > 1) {
      const select = element("select", {
        class: "time",
        onchange: () => {
          state.time = Number(select.value);
          updateGrid();
          render();
        },
      });
      group.times.forEach((t, i) => select.append(element("option", { value: i }, "t = " + t + " s")));
      controls.append(element("label", {}, "error frame along the camera path: ", select));
    }

    // Grid: families in the order they come.
    const grid = section.querySelector(".grid");
    const families = [];
    group.entries.forEach((entry, index) => {
      let family = families.find((f) => f.name === entry.family);
      if (!family) {
        family = { name: entry.family, entries: [] };
        families.push(family);
      }
      family.entries.push(index);
    });
    const cards = [];
    for (const family of families) {
      const row = element("div", { class: "cards" });
      grid.append(element("div", { class: "family" }, element("h3", {}, family.name), row));
      for (const index of family.entries) {
        const entry = group.entries[index];
        const image = element("img", { alt: entry.label });
        const flipButton = element("button", { class: "flip-toggle", title: "show the FLIP error map (black: none, yellow: large)" }, "FLIP map");
        const card = element(
          "figure",
          { class: "card" + (entry.error ? " failed" : ""), "data-entry": index },
          element("div", { class: "thumb" }, image, element("span", { class: "missing" })),
          element(
            "figcaption",
            {},
            element("span", { class: "name" }, entry.label.replace(/\//g, "/\u200b")),
            entry.figures ? figureLine(entry.figures) : null,
            entry.error ? element("span", { class: "err" }, entry.error) : null,
            element(
              "span",
              { class: "buttons" },
              flipButton,
              element("button", { title: "compare: left side", onclick: () => pick("a", index) }, "A"),
              element("button", { title: "compare: right side", onclick: () => pick("b", index) }, "B")
            )
          )
        );
        const item = { entry, index, card, image, flipButton, flip: false };
        flipButton.addEventListener("click", () => {
          item.flip = !item.flip;
          flipButton.classList.toggle("on", item.flip);
          updateCard(item);
        });
        cards.push(item);
        row.append(card);
      }
    }

    function updateCard(item) {
      const frame = frameOf(item.entry);
      item.flipButton.disabled = !(frame && frame.flip);
      const missing = item.card.querySelector(".missing");
      if (!frame) {
        item.image.removeAttribute("src");
        missing.textContent = item.entry.error ? "no image: it failed" : "no image at this time";
        return;
      }
      missing.textContent = "";
      item.image.src = item.flip && frame.flip ? frame.flip : frame.png;
    }

    function updateGrid() {
      cards.forEach(updateCard);
      cards.forEach((c) => {
        c.card.classList.toggle("selected-a", c.index === state.a);
        c.card.classList.toggle("selected-b", c.index === state.b);
      });
    }

    function pick(side, index) {
      state[side] = index;
      (side === "a" ? selectA : selectB).value = index;
      updateGrid();
      render();
    }

    // Comparison view.
    const compare = section.querySelector(".compare");
    const entryOptions = () =>
      group.entries.map((e, i) => element("option", { value: i }, e.label));
    const selectA = element("select", { class: "pick-a", onchange: () => pick("a", Number(selectA.value)) }, ...entryOptions());
    const selectB = element("select", { class: "pick-b", onchange: () => pick("b", Number(selectB.value)) }, ...entryOptions());
    selectA.value = state.a;
    selectB.value = state.b;
    const modeButtons = ["slider", "flicker", "toggle"].map((mode) =>
      element("button", { "data-mode": mode, onclick: () => setMode(mode) }, mode)
    );
    const showSelect = element(
      "select",
      { class: "show", onchange: () => { state.show = showSelect.value; render(); } },
      element("option", { value: "image" }, "images"),
      element("option", { value: "flip", title: "each against its reference" }, "FLIP maps")
    );
    const exposure = element("input", { type: "range", min: -10, max: 10, step: 0.5, value: 0, class: "exposure" });
    const exposureLabel = element("output", {}, "+0 EV");
    exposure.addEventListener("input", () => {
      state.exposure = Number(exposure.value);
      exposureLabel.textContent = (state.exposure >= 0 ? "+" : "") + state.exposure + " EV";
      render();
    });
    const resetExposure = element("button", { onclick: () => { exposure.value = 0; exposure.dispatchEvent(new Event("input")); } }, "reset");
    const zoomSelect = element(
      "select",
      { class: "zoom-factor", onchange: () => { state.zoom = Number(zoomSelect.value); drawZoom(); } },
      ...[2, 4, 8, 16, 32].map((z) => element("option", { value: z }, z + "x"))
    );
    zoomSelect.value = state.zoom;
    const swapButton = element("button", { onclick: () => { state.showingB = !state.showingB; applyMode(); } }, "show the other (space)");
    const status = element("span", { class: "note" });
    compare.append(
      element("h3", {}, "compare"),
      element(
        "div",
        { class: "controls" },
        element("label", {}, "A (left) ", selectA),
        element("label", {}, "B (right) ", selectB),
        element("span", {}, ...modeButtons, " ", swapButton),
        element("label", {}, "show ", showSelect),
        element("label", {}, "exposure ", exposure, " ", exposureLabel, " ", resetExposure),
        element("label", {}, "zoom ", zoomSelect),
        status
      )
    );
    const canvasA = element("canvas", { class: "a" });
    const canvasB = element("canvas", { class: "b" });
    const handle = element("div", { class: "handle", title: "drag to move the split" });
    const cropBox = element("div", { class: "crop" });
    const tagA = element("span", { class: "tag a" });
    const tagB = element("span", { class: "tag b" });
    const stage = element("div", { class: "stage", tabindex: 0, title: "click or drag: choose the zoomed crop; space: show the other image" }, canvasA, canvasB, handle, cropBox, tagA, tagB);
    const zoomA = element("canvas", { class: "zoom-a", width: 256, height: 256 });
    const zoomB = element("canvas", { class: "zoom-b", width: 256, height: 256 });
    const zoomCaptionA = element("figcaption");
    const zoomCaptionB = element("figcaption");
    compare.append(
      element(
        "div",
        { class: "views" },
        stage,
        element("div", { class: "zoom" }, element("figure", {}, zoomA, zoomCaptionA), element("figure", {}, zoomB, zoomCaptionB))
      ),
      element("p", { class: "note" }, "Slider: drag the handle. Flicker: the two alternate twice a second. Toggle: space or the button. The zoom shows the same crop of both, nearest-neighbour; exposure scales the linear radiance of the HDR copies (magenta: NaN or infinite pixels).")
    );

    let flickerTimer = null;
    function setMode(mode) {
      state.mode = mode;
      modeButtons.forEach((b) => b.classList.toggle("on", b.dataset.mode === mode));
      clearInterval(flickerTimer);
      flickerTimer = null;
      if (mode === "flicker") {
        flickerTimer = setInterval(() => { state.showingB = !state.showingB; applyMode(); }, 500);
      }
      applyMode();
    }

    function applyMode() {
      const slider = state.mode === "slider";
      handle.style.display = slider ? "" : "none";
      swapButton.disabled = slider;
      canvasB.style.clipPath = slider ? "inset(0 0 0 " + (state.split * 100).toFixed(2) + "%)" : "none";
      canvasB.style.visibility = slider || state.showingB ? "visible" : "hidden";
      handle.style.left = (state.split * 100).toFixed(2) + "%";
      stage.dataset.split = state.split.toFixed(4);
      tagA.style.display = slider || !state.showingB ? "" : "none";
      tagB.style.display = slider || state.showingB ? "" : "none";
      drawZoom();
    }

    stage.addEventListener("keydown", (event) => {
      if (event.key === " " && state.mode !== "slider") {
        event.preventDefault();
        state.showingB = !state.showingB;
        applyMode();
      }
    });

    // Dragging: the handle moves the split; anywhere else chooses the zoomed crop.
    let dragging = null;
    const fraction = (event) => {
      const rect = stage.getBoundingClientRect();
      if (!rect.width || !rect.height) return { x: state.split, y: 0.5 };
      return {
        x: Math.min(1, Math.max(0, (event.clientX - rect.left) / rect.width)),
        y: Math.min(1, Math.max(0, (event.clientY - rect.top) / rect.height)),
      };
    };
    const onDrag = (event) => {
      const f = fraction(event);
      if (dragging === "split") {
        state.split = f.x;
        applyMode();
      } else if (dragging === "crop") {
        state.crop = { x: f.x * imageWidth(), y: f.y * imageHeight() };
        drawZoom();
      }
    };
    stage.addEventListener("pointerdown", (event) => {
      dragging = event.target === handle ? "split" : "crop";
      stage.setPointerCapture(event.pointerId);
      stage.focus({ preventScroll: true });
      onDrag(event);
    });
    stage.addEventListener("pointermove", (event) => { if (dragging) onDrag(event); });
    const stop = () => { dragging = null; };
    stage.addEventListener("pointerup", stop);
    stage.addEventListener("pointercancel", stop);

    // The stage's image size: the larger of the two (one side may have no image).
    const imageWidth = () => Math.max(canvasA.width, canvasB.width);
    const imageHeight = () => Math.max(canvasA.height, canvasB.height);

    function drawZoom() {
      const width = imageWidth();
      const height = imageHeight();
      if (!width || !height || !state.crop) return;
      const size = Math.max(1, Math.round(256 / state.zoom));
      const cw = Math.min(size, width);
      const ch = Math.min(size, height);
      const x0 = Math.round(Math.min(Math.max(state.crop.x - cw / 2, 0), width - cw));
      const y0 = Math.round(Math.min(Math.max(state.crop.y - ch / 2, 0), height - ch));
      for (const [target, source] of [[zoomA, canvasA], [zoomB, canvasB]]) {
        const context = target.getContext("2d");
        context.imageSmoothingEnabled = false;
        context.clearRect(0, 0, 256, 256);
        if (source.width) context.drawImage(source, x0, y0, cw, ch, 0, 0, 256 * cw / size, 256 * ch / size);
      }
      const scale = stage.clientWidth / width;
      Object.assign(cropBox.style, {
        left: x0 * scale + "px",
        top: y0 * scale + "px",
        width: cw * scale + "px",
        height: ch * scale + "px",
      });
      zoomCaptionA.textContent = "A, pixels " + x0 + ".." + (x0 + cw - 1) + " x " + y0 + ".." + (y0 + ch - 1);
      zoomCaptionB.textContent = "B, the same crop";
    }

    // Draws one side into a new canvas: the HDR copy at the exposure (else the PNG), or the
    // FLIP map. Returns the canvas and a note (or null).
    async function drawSide(entry) {
      const canvas = document.createElement("canvas");
      const note = await drawInto(canvas, entry);
      return { canvas, note };
    }

    async function drawInto(canvas, entry) {
      const frame = frameOf(entry);
      if (!frame) {
        canvas.width = canvas.height = 0;
        return entry.label + ": no image at this time";
      }
      if (state.show === "flip") {
        if (frame.flip) {
          drawImage(canvas, await loadImage(frame.flip));
          return null;
        }
        drawImage(canvas, await loadImage(frame.png));
        return entry.label + " has no FLIP map (shown as rendered)";
      }
      if (frame.hdr) {
        try {
          drawHdr(canvas, await loadHdr(frame.hdr), state.exposure);
          return null;
        } catch (error) {
          drawImage(canvas, await loadImage(frame.png));
          return entry.label + ": " + error.message + " (the PNG is shown, without exposure)";
        }
      }
      drawImage(canvas, await loadImage(frame.png));
      return state.exposure !== 0 ? entry.label + " has no HDR copy (exposure not applied)" : null;
    }

    // Renders both sides off screen and shows them only if no later render started meanwhile
    // (an HDR copy may load slowly). Failures go to the status line, never to the console.
    let renderCount = 0;
    async function render() {
      const ticket = ++renderCount;
      const a = group.entries[state.a];
      const b = group.entries[state.b];
      let sides;
      try {
        sides = await Promise.all([drawSide(a), drawSide(b)]);
      } catch (error) {
        if (ticket === renderCount) status.textContent = error.message;
        return;
      }
      if (ticket !== renderCount) return;
      tagA.textContent = "A: " + a.label;
      tagB.textContent = "B: " + b.label;
      [[canvasA, sides[0].canvas], [canvasB, sides[1].canvas]].forEach(([shown, drawn]) => {
        shown.width = drawn.width;
        shown.height = drawn.height;
        if (drawn.width) shown.getContext("2d").drawImage(drawn, 0, 0);
      });
      const width = Math.max(imageWidth(), 1);
      const scale = Math.max(1, Math.floor(512 / width));
      for (const canvas of [canvasA, canvasB]) {
        canvas.style.width = canvas.width * scale + "px";
        canvas.style.height = canvas.height * scale + "px";
      }
      // The stage takes the larger image's size (one side may have none).
      stage.style.width = width * scale + "px";
      stage.style.height = imageHeight() * scale + "px";
      status.textContent = sides.map((s) => s.note).filter((n) => n).join("; ");
      // The crop starts at the image's centre, once its size is known.
      if (!state.crop) state.crop = { x: imageWidth() / 2, y: imageHeight() / 2 };
      applyMode();
      section.dataset.renders = String(Number(section.dataset.renders || 0) + 1);
    }

    updateGrid();
    setMode("slider");
    return render();
  }

  // ---- results table ----------------------------------------------------------------------
  function setupTable() {
    const table = document.getElementById("results-table");
    if (!table) return;
    const body = table.tBodies[0];
    const headings = Array.from(table.tHead.rows[0].cells);
    const number = (text) => {
      if (text === "") return null;
      if (text === "inf") return Infinity;
      if (text === "-inf") return -Infinity;
      const v = parseFloat(text);
      return isNaN(v) ? null : v;
    };
    for (const row of body.rows) {
      for (const cell of row.cells) if (cell.dataset.v && !cell.title) cell.title = cell.dataset.v;
    }
    headings.forEach((heading, column) => {
      heading.addEventListener("click", () => {
        const ascending = !heading.classList.contains("sorted-asc");
        headings.forEach((h) => h.classList.remove("sorted-asc", "sorted-desc"));
        heading.classList.add(ascending ? "sorted-asc" : "sorted-desc");
        const numeric = heading.dataset.kind === "num";
        const rows = Array.from(body.rows);
        rows.sort((r, s) => {
          const x = r.cells[column].dataset.v;
          const y = s.cells[column].dataset.v;
          if (!numeric) return ascending ? x.localeCompare(y) : y.localeCompare(x);
          const a = number(x);
          const b = number(y);
          if (a === b) return 0;
          if (a === null) return 1; // missing figures last, either way
          if (b === null) return -1;
          return ascending ? (a < b ? -1 : 1) : (a < b ? 1 : -1);
        });
        rows.forEach((row) => body.append(row));
      });
    });
    const scene = document.getElementById("filter-scene");
    const family = document.getElementById("filter-family");
    const failed = document.getElementById("filter-failed");
    const count = document.getElementById("row-count");
    const filter = () => {
      let shown = 0;
      for (const row of body.rows) {
        const visible =
          (!scene.value || row.dataset.scene === scene.value) &&
          (!family.value || row.dataset.family === family.value) &&
          (!failed.checked || row.classList.contains("failed") || row.classList.contains("has-nan"));
        row.hidden = !visible;
        shown += visible;
      }
      count.textContent = shown + " of " + body.rows.length + " rows";
    };
    [scene, family, failed].forEach((control) => control.addEventListener("change", filter));
    filter();
  }

  setupTable();
  const sections = Array.from(document.querySelectorAll("section.group"));
  Promise.allSettled(
    sections.map((section) => setupGroup(section, data.groups[Number(section.dataset.group)]))
  ).then(() => { document.body.dataset.ready = "1"; });
})();
