// The page of `lrdslam report` (docs/report.md): draws the run data that src/lrd/report/run_data.cc
// put into #report-data with uPlot and common.js (inlined before this script). No network:
// everything is in the page.
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("report-data").textContent);
  const summary = data.summary || {};
  const root = document.getElementById("report");
  const charts = [];  // what the browser test checks: one entry per chart drawn
  // Time on the charts: seconds since the run's first frame (stamps are often Unix times).
  const T0 = data.frames.t.length ? data.frames.t[0] : 0;
  const since = (t) => t - T0;
  const STATE_COLOURS = {"lost": "rgba(220, 50, 47, 0.18)", "not-initialized": "rgba(130, 130, 130, 0.15)",
                         "not-localized": "rgba(181, 137, 0, 0.18)"};

  const {el, num, table, chartBox, ramp, equalRanges, drawPolyline} = window.lrdCommon;
  const section = (id, title, intro) => window.lrdCommon.section(root, id, title, intro);
  function register(id, plot) {
    charts.push({id: id, plot: plot});
    return plot;
  }

  // ---- Summary -----------------------------------------------------------------------------
  function summarySection() {
    root.append(el("h1", {}, "lrd-slam run: " + data.run));
    root.append(el("p", {class: "path"}, data.run_dir + (data.ground_truth ? " · ground truth " + data.ground_truth : "")));
    const s = section("summary", "Summary");
    const counts = [["frames", summary.frames], ["tracked", summary.tracked], ["lost", summary.lost],
                    ["not initialized", summary.not_initialized], ["not localized", summary.not_localized],
                    ["keyframes", summary.keyframes], ["map points", summary.map_points],
                    ["loops closed", (summary.loops || []).length], ["relocalizations", summary.relocalizations],
                    ["wall time (s)", num(summary.wall_seconds, 2)]];
    s.append(el("div", {class: "cards"}, counts.map(([k, v]) => el("div", {class: "card"}, [el("b", {}, num(v)), k]))));
    const tables = el("div", {class: "tables"});
    s.append(tables);
    if (summary.ate) {
      const a = summary.ate;
      tables.append(el("div", {}, [el("h3", {}, "ATE (cm)"), table([["RMSE", num(100 * a.rmse)], ["mean", num(100 * a.mean)],
        ["median", num(100 * a.median)], ["max", num(100 * a.max)], ["pairs", a.pairs]])]));
    }
    if (summary.rpe)
      tables.append(el("div", {}, [el("h3", {}, "RPE over 1 s"), table([["translation RMSE (cm)", num(100 * summary.rpe.trans_rmse)],
        ["rotation RMSE (deg)", num(summary.rpe.rot_rmse)]])]));
    const config = [["mode", summary.mode], ["segmentation", summary.segmentation], ["camera", summary.camera],
                    ["vocabulary", summary.vocabulary], ["loop closing", summary.loop_closing],
                    ["mean mask age (frames)", num(summary.mean_mask_age, 2)]];
    tables.append(el("div", {}, [el("h3", {}, "Configuration"), table(config.map(([k, v]) => [k, v === undefined ? "–" : String(v)]))]));
    if (summary.dynamic_flags) {
      const f = summary.dynamic_flags;
      tables.append(el("div", {}, [el("h3", {}, "Dynamic flags (synthetic truth)"), table([["precision", num(f.precision)],
        ["recall", num(f.recall)], ["frames", f.frames]])]));
    }
    if (summary.dense) {
      const d = summary.dense, rows = [["points", d.points], ["repair fill ratio", num(d.repair && d.repair.fill_ratio)]];
      if (d.map) rows.push(["ghost ratio", num(d.map.ghost_ratio)], ["completeness", num(d.map.completeness)]);
      tables.append(el("div", {}, [el("h3", {}, "Dense map"), table(rows)]));
    }
    for (const n of data.notes || []) s.append(el("p", {class: "note"}, n));
  }

  // ---- Trajectory --------------------------------------------------------------------------
  function trajectoryChart(parent, id, title, axes) {
    const T = data.trajectory, est = [T.est[axes[0]], T.est[axes[1]]];
    const ref = T.gt_path ? [T.gt_path[axes[0]], T.gt_path[axes[1]]] : est;
    const maxError = T.error && T.error.length ? Math.max(...T.error) : 0;
    const W = 440, H = 380;
    const [rx, ry] = equalRanges(ref[0].concat(est[0]), ref[1].concat(est[1]), W - 70, H - 60);
    const box = chartBox(parent, id, title);
    const tip = el("div", {class: "tip"});
    const series = [{}];
    const rows = [null];
    if (T.gt_path) {
      series.push({label: "ground truth", stroke: "#555", facets: [{scale: "x", auto: false}, {scale: "y", auto: false}],
                   paths: (u, i) => drawPolyline(u, i, () => "rgba(80, 80, 80, 0.55)")});
      rows.push(ref);
    }
    series.push({label: "estimate", stroke: "#268bd2", facets: [{scale: "x", auto: false}, {scale: "y", auto: false}],
                 paths: (u, i) => drawPolyline(u, i, (k) => T.error ? ramp(T.error[k] / (maxError || 1)) : "#268bd2")});
    rows.push(est);
    const keep = (fixed) => (u, lo, hi) => (lo === null || hi === null ? fixed : [lo, hi]);
    const plot = new uPlot({
      mode: 2, width: W, height: H, legend: {show: false},
      cursor: {drag: {x: true, y: true, uni: 20}, points: {show: false}, dataIdx: () => null},
      scales: {x: {time: false, range: keep(rx)}, y: {range: keep(ry)}},
      axes: [{label: axes[0] + " (m)"}, {label: axes[1] + " (m)"}],
      series: series,
      hooks: {setCursor: [(u) => hover(u, est, tip)]},
    }, rows, box);
    plot.over.append(tip);
    if (T.error) box.append(el("div", {class: "legend"}, ["error: ", el("span", {class: "ramp"}), " 0 – " + num(100 * maxError, 2) + " cm",
      T.gt_path ? " · grey: ground truth" : ""]));
    return register(id, plot);
  }
  // The frame under the cursor: the nearest estimated position within 12 px.
  function hover(u, est, tip) {
    const {left, top} = u.cursor;
    let best = -1, bestD = 144;
    if (left >= 0)
      for (let i = 0; i < est[0].length; i++) {
        const dx = u.valToPos(est[0][i], "x") - left, dy = u.valToPos(est[1][i], "y") - top;
        if (dx * dx + dy * dy < bestD) { bestD = dx * dx + dy * dy; best = i; }
      }
    if (best < 0) { tip.style.display = "none"; return; }
    const T = data.trajectory;
    tip.textContent = "t " + since(T.t[best]).toFixed(3) + " s" + (T.error ? " · error " + num(100 * T.error[best], 2) + " cm" : "");
    tip.style.display = "block";
    tip.style.left = (u.valToPos(est[0][best], "x") + 10) + "px";
    tip.style.top = (u.valToPos(est[1][best], "y") - 10) + "px";
  }
  function trajectorySection() {
    const T = data.trajectory;
    const s = section("trajectory", "Trajectory", "In " + T.frame + ". Drag to zoom, double-click to reset; hover for a frame's time and error.");
    if (!T.t.length) { s.append(el("p", {class: "note"}, "No tracked frame: nothing to draw.")); return; }
    const row = el("div", {class: "row"});
    s.append(row);
    const own = !T.gt;  // the first camera's frame: x right, y down, z forward
    trajectoryChart(row, "trajectory-top", own ? "Top view (x–z)" : "Top view (x–y)", own ? ["x", "z"] : ["x", "y"]);
    trajectoryChart(row, "trajectory-side", own ? "Side view (x–y)" : "Side view (x–z)", own ? ["x", "y"] : ["x", "z"]);
  }

  // ---- Error and events over time ----------------------------------------------------------
  // Spans of frames in a state other than ok, as [t0, t1, state].
  function stateSpans() {
    const F = data.frames, spans = [];
    for (let i = 0; i < F.t.length; i++) {
      if (F.state[i] === "ok") continue;
      const last = spans[spans.length - 1];
      if (last && last[2] === F.state[i] && last[3] === i - 1) { last[1] = since(F.t[i]); last[3] = i; }
      else spans.push([since(F.t[i]), since(F.t[i]), F.state[i], i]);
    }
    return spans;
  }
  // Frames tracked again after a loss: relocalizations.
  function relocalizationTimes() {
    const F = data.frames, out = [];
    for (let i = 1; i < F.t.length; i++) if (F.state[i] === "ok" && (F.state[i - 1] === "lost" || F.state[i - 1] === "not-localized")) out.push(since(F.t[i]));
    return out;
  }
  function eventsHook(u) {
    const ctx = u.ctx, top = u.bbox.top, height = u.bbox.height;
    const x = (t) => u.valToPos(t, "x", true);
    ctx.save();
    for (const [t0, t1, state] of stateSpans()) {
      ctx.fillStyle = STATE_COLOURS[state] || "rgba(0,0,0,0.1)";
      ctx.fillRect(x(t0), top, Math.max(x(t1) - x(t0), 2 * uPlot.pxRatio), height);
    }
    const marks = [[relocalizationTimes(), "#b58900"], [(summary.loops || []).map((l) => since(l.timestamp)), "#859900"]];
    ctx.lineWidth = 2 * uPlot.pxRatio;
    for (const [times, colour] of marks)
      for (const t of times) {
        ctx.strokeStyle = colour;
        ctx.beginPath(); ctx.moveTo(x(t), top); ctx.lineTo(x(t), top + height); ctx.stroke();
      }
    ctx.restore();
  }
  function errorSection() {
    const T = data.trajectory, F = data.frames;
    const s = section("errors", "Error and tracking over time",
      "Shaded: lost (red), not initialized (grey), not localized in a loaded map (amber). Lines: relocalizations (amber), loop closures (green).");
    if (!F.t.length) return;
    const box = chartBox(s, "ape-over-time", T.error ? "Absolute position error (cm) and inliers" : "Inliers per frame");
    // One x axis for both: the frames' stamps; APE where a frame has a pose associated with the truth.
    const ape = new Map();
    if (T.error) T.t.forEach((t, i) => ape.set(t.toFixed(4), 100 * T.error[i]));
    const apeRow = F.t.map((t) => (ape.has(t.toFixed(4)) ? ape.get(t.toFixed(4)) : null));
    const series = [{label: "t (s)", value: (u, v) => (v === null ? "–" : v.toFixed(3))}];
    const rows = [F.t.map(since)];
    if (T.error) { series.push({label: "APE (cm)", stroke: "#dc322f", width: 1.5, scale: "cm", spanGaps: false}); rows.push(apeRow); }
    series.push({label: "inliers", stroke: "#268bd2", width: 1, scale: "n"});
    rows.push(F.inliers);
    const axes = [{label: "time since the first frame (s)"}];
    if (T.error) axes.push({scale: "cm", label: "APE (cm)"});
    axes.push({scale: "n", label: "inliers", side: T.error ? 1 : 3, grid: {show: !T.error}});
    register("ape-over-time", new uPlot({width: 940, height: 300, scales: {x: {time: false}}, series: series, axes: axes,
                                          hooks: {drawClear: [eventsHook]}}, rows, box));
    flagsChart(s);
  }

  // Dynamic flags against the synthetic benchmark's person masks, on the frames the run scored.
  function flagsChart(parent) {
    const G = data.flags;
    if (!G || !G.frame.length) return;
    const ratio = (a, b) => a.map((v, i) => (v + b[i] > 0 ? v / (v + b[i]) : null));
    const precision = ratio(G.true_positive, G.false_positive), recall = ratio(G.true_positive, G.false_negative);
    const box = chartBox(parent, "flags-over-time", "Dynamic-flag precision and recall per scored frame (keypoints on people flagged dynamic)");
    register("flags-over-time", new uPlot({width: 940, height: 240, scales: {x: {time: false}, y: {range: [0, 1]}},
      series: [{label: "frame"}, {label: "precision", stroke: "#6c71c4", width: 1.5, points: {show: true, size: 4}},
               {label: "recall", stroke: "#2aa198", width: 1.5, points: {show: true, size: 4}}],
      axes: [{label: "frame"}, {label: "share"}]}, [G.frame, precision, recall], box));
  }

  // ---- Time per stage ----------------------------------------------------------------------
  const STAGES = [["extraction", "#268bd2"], ["mask_wait", "#d33682"], ["geometry", "#6c71c4"], ["tracking", "#2aa198"],
                  ["waiting", "#b58900"], ["mapping", "#cb4b16"]];
  function timeSection() {
    const F = data.frames;
    // Y: OpenCV ORB on this run's frames, timed by `run --report` after the run (see the README's
    // Benchmarks): times on the right axis are multiples of it.
    const Y = data.yardstick && data.yardstick.ms ? data.yardstick.ms : null;
    const median = summary.per_frame && summary.per_frame.total && summary.per_frame.total.median_ms;
    const s = section("time", "Time per frame",
      "Stacked: the stages of the tracking thread (ms); segmentation runs in its own thread and is drawn apart. " +
      "Median total " + num(median, 2) + " ms" + (Y ? " = " + num(median / Y, 2) + " Y, where Y = " + num(Y, 2) +
      " ms is OpenCV ORB (1000 features) on " + data.yardstick.frames + " of this run's frames, timed after the run." : "."));
    const inY = Y ? [{scale: "y", side: 1, label: "× Y", grid: {show: false}, values: (u, ticks) => ticks.map((t) => (t / Y).toFixed(1))}] : [];
    if (!F.t.length) return;
    const box = chartBox(s, "stage-times", "Per-stage time over the frames (stacked, ms)");
    const rows = [F.index], series = [{label: "frame"}], bands = [];
    let below = F.index.map(() => 0);
    STAGES.forEach(([name, colour], k) => {
      const raw = F.stages[name], stacked = raw.map((v, i) => v + below[i]);
      series.push({label: name, stroke: colour, fill: colour + "99", width: 1, value: (u, v, si, i) => (i === null ? "–" : raw[i].toFixed(2))});
      rows.push(stacked);
      if (k > 0) bands.push({series: [k + 1, k]});
      below = stacked;
    });
    series.push({label: "segmentation (own thread)", stroke: "#586e75", width: 1, dash: [4, 3]});
    rows.push(F.stages.segmentation);
    // Each stage's fill reaches down to the stage below it, not to zero.
    register("stage-times", new uPlot({width: 940, height: 300, scales: {x: {time: false}}, series: series, bands: bands,
                                        axes: [{label: "frame"}, {label: "ms"}].concat(inY)}, rows, box));
    const hbox = chartBox(s, "time-distribution", "Distribution of the total time per frame");
    const totals = F.total.slice().sort((a, b) => a - b), bins = 30;
    const lo = totals[0], hi = totals[totals.length - 1], w = Math.max((hi - lo) / bins, 1e-3);
    const centres = [], counts = [];
    for (let b = 0; b < bins; b++) { centres.push(lo + (b + 0.5) * w); counts.push(0); }
    for (const v of totals) counts[Math.min(Math.floor((v - lo) / w), bins - 1)]++;
    register("time-distribution", new uPlot({width: 940, height: 220, scales: {x: {time: false}},
      series: [{label: "ms"}, {label: "frames", stroke: "#268bd2", fill: "#268bd266", paths: uPlot.paths.bars({size: [0.9]})}],
      axes: [{label: "total ms per frame"}, {label: "frames"}]}, [centres, counts], hbox));
  }

  // ---- Sample frames -----------------------------------------------------------------------
  function sampleSection() {
    const samples = data.samples || [];
    if (!samples.length) return;
    const s = section("samples", "Sample frames",
      "Chosen by the run (lrdslam run --report): the largest errors, the most keypoints removed by the geometry check, " +
      "the oldest masks. Red: dynamic mask; green circles: keypoints used for tracking; magenta crosses: removed.");
    const grid = el("div", {class: "samples"});
    s.append(grid);
    for (const f of samples) {
      const caption = "frame " + f.frame + " · " + f.reasons.join(", ") + " · " + f.kept + " kept, " + f.removed + " removed" +
        (f.mask_age >= 0 ? " · mask age " + f.mask_age : "") + (f.error !== null ? " · error " + num(100 * f.error, 2) + " cm" : "");
      grid.append(el("figure", {class: "image sample"}, [el("img", {src: f.src, alt: "frame " + f.frame}), el("figcaption", {}, caption)]));
    }
  }

  // ---- Background repair -------------------------------------------------------------------
  function repairSection() {
    const repairs = data.repairs || [];
    if (!repairs.length) return;
    const s = section("repair", "Background repair",
      "The keyframes with the most dynamic pixels (§2.8): colour before and after the repair on top, depth " +
      "(0–5 m, near red) below; black where nothing could be filled.");
    for (const r of repairs) {
      const caption = "t " + since(r.timestamp).toFixed(2) + " s · " + r.dynamic_pixels + " dynamic pixels, " +
        r.filled_pixels + " filled (" + num(100 * r.filled_pixels / Math.max(r.dynamic_pixels, 1), 1) + " %)";
      s.append(el("figure", {class: "image repair"}, [el("img", {src: r.src, alt: "repair"}), el("figcaption", {}, caption)]));
    }
  }

  // ---- Images ------------------------------------------------------------------------------
  function imageSection() {
    if (!data.images || !data.images.length) return;
    const s = section("maps", "Maps");
    for (const img of data.images) {
      const fig = el("figure", {class: "image"}, [el("img", {src: img.src, alt: img.title}), el("figcaption", {}, img.title + " (" + img.file + ")")]);
      s.append(fig);
    }
  }

  // ---- 3-D map (web/map3d.js, with three.js, inlined when the run wrote a map) ---------------
  function map3dSection() {
    if (!data.map3d || !window.lrdMap3d) return;
    const s = section("map3d", "3-D map", "The dense map (coloured), the sparse map's points (dark) and the keyframes " +
      "(red), in the first camera's frame. Drag to orbit, wheel to zoom, right-drag to pan.");
    window.lrdMap3d(s, data.map3d, register);
  }

  summarySection();
  trajectorySection();
  errorSection();
  timeSection();
  sampleSection();
  repairSection();
  imageSection();
  map3dSection();
  window.lrdReport = {charts: charts.map((c) => c.id), images: (data.images || []).length, samples: (data.samples || []).length};
  window.lrdCommon.markReady(charts.map((c) => c.id));
})();
