// The page of a benchmark (docs/report.md): bench_dynamic's tables as the paper gives them
// (Tables 4-7: ATE and RPE; Table 10: time per frame; the improvement rate eta, Eq. 12) and per
// preset every mode's trajectory against the ground truth on one plot.
// src/lrd/report/benchmark_data.cc put the data into #report-data; uPlot and common.js are inlined
// before this script.
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("report-data").textContent);
  const results = data.results, presets = data.presets, modes = data.modes;
  const root = document.getElementById("report");
  const charts = [];
  const {el, num, table, chartBox, equalRanges, drawPolyline} = window.lrdCommon;
  const section = (id, title, intro) => window.lrdCommon.section(root, id, title, intro);
  const MODE_COLOURS = {"static": "#dc322f", "semantic": "#b58900", "geometric": "#6c71c4", "full": "#268bd2",
                        "full-sync": "#2aa198"};
  const FALLBACK_COLOURS = ["#859900", "#d33682", "#cb4b16", "#586e75"];
  const colourOf = (mode) => MODE_COLOURS[mode] || FALLBACK_COLOURS[modes.indexOf(mode) % FALLBACK_COLOURS.length];
  const runs = new Map(results.runs.map((r) => [r.preset + "/" + r.mode, r]));
  const run = (preset, mode) => runs.get(preset + "/" + mode);
  const others = modes.filter((m) => m !== "static");

  function header() {
    root.append(el("h1", {}, "lrd-slam benchmark: " + data.run));
    root.append(el("p", {class: "path"}, data.run_dir));
    root.append(el("p", {class: "intro"}, "Segmenter: " + (results.segmenter || "–") + ". Synthetic presets" +
      (results.seed !== undefined ? ", seed " + results.seed : "") +
      (results.frames > 0 ? ", first " + results.frames + " frames" : ", default lengths") +
      ". Time per frame excludes image decoding; Y = median OpenCV ORB detectAndCompute (1000 features) on the same frames."));
  }

  // Tables 4-7: per preset, per mode RMSE / mean / median / std of one error statistic.
  function errorTable(parent, title, key, scale, unit) {
    const head = ["sequence"];
    for (const m of modes) head.push(m + " RMSE", "mean", "median", "std");
    const rows = presets.map((p) => [p].concat(...modes.map((m) => {
      const s = run(p, m) && run(p, m)[key];
      return s ? [s.rmse, s.mean, s.median, s.std].map((v) => num(scale * v, 2)) : ["–", "–", "–", "–"];
    })));
    parent.append(el("h3", {}, title + " (" + unit + ")"), el("div", {class: "wide"}, table(rows, head)));
  }
  function accuracySection() {
    const s = section("accuracy", "Accuracy (Tables 4-7)", "Per sequence and mode: RMSE, mean, median and standard deviation.");
    errorTable(s, "Tables 4-5: ATE", "ate_m", 100, "cm");
    errorTable(s, "Table 6: RPE translation", "rpe_trans_m_per_s", 100, "cm/s");
    errorTable(s, "Table 7: RPE rotation", "rpe_rot_deg_per_s", 1, "deg/s");
    ateChart(s);
  }
  // ATE RMSE per preset and mode on a log axis (static's errors are often 10-100x the others').
  function ateChart(parent) {
    const xs = presets.map((p, i) => i);
    const series = [{label: "preset", value: (u, v) => (v === null ? "–" : presets[v])}];
    const rows = [xs];
    for (const m of modes) {
      series.push({label: m, stroke: colourOf(m), width: 1.5, points: {show: true, size: 7, fill: colourOf(m)},
                   value: (u, v) => (v === null ? "–" : v.toFixed(2) + " cm")});
      rows.push(presets.map((p) => (run(p, m) && run(p, m).ate_m && run(p, m).ate_m.rmse > 0 ? 100 * run(p, m).ate_m.rmse : null)));
    }
    const box = chartBox(parent, "ate-by-preset", "ATE RMSE (cm, log scale) per sequence and mode");
    const plot = new uPlot({
      width: 940, height: 300, series: series,
      scales: {x: {time: false, range: [-0.5, presets.length - 0.5]}, y: {distr: 3}},
      axes: [{splits: () => xs, values: (u, ticks) => ticks.map((t) => presets[t] || ""), rotate: -20, size: 60},
             {label: "ATE RMSE (cm)"}],
    }, rows, box);
    charts.push("ate-by-preset");
    return plot;
  }

  // The improvement rate eta = (static - mode) / static (Eq. 12), in %.
  function etaSection() {
    if (!modes.includes("static") || !others.length) return;
    const s = section("eta", "Improvement over static (eta, Eq. 12)", "ATE RMSE / RPE translation RMSE / RPE rotation RMSE, in %.");
    const rows = presets.map((p) => [p].concat(others.map((m) => {
      const e = run(p, m) && run(p, m).eta_percent;
      return e ? num(e.ate_rmse, 1) + " / " + num(e.rpe_trans_rmse, 1) + " / " + num(e.rpe_rot_rmse, 1) : "–";
    })));
    s.append(table(rows, ["sequence"].concat(others)));
  }

  // Table 10: mean and median time per frame, in ms and as multiples of Y.
  function timeSection() {
    const s = section("time", "Time per frame (Table 10)", "ms, and in brackets as multiples of Y, measured in each run beside its own extraction (the Y column: each mode's, in order).");
    const head = ["sequence", "Y (ms)"];
    for (const m of modes) head.push(m + " mean", "median");
    const rows = presets.map((p) => {
      const ys = modes.map((m) => (run(p, m) ? num(run(p, m).y_ms, 2) : "–")).join(" / ");
      return [p, ys].concat(...modes.map((m) => {
        const r = run(p, m);
        return r ? [num(r.time_ms.mean, 1) + " (" + num(r.time_y.mean, 2) + " Y)", num(r.time_ms.median, 1) + " (" + num(r.time_y.median, 2) + " Y)"]
                 : ["–", "–"];
      }));
    });
    s.append(el("div", {class: "wide"}, table(rows, head)));
  }

  // Dynamic keypoint flags against the synthetic benchmark's ground-truth masks.
  function flagsSection() {
    if (!others.some((m) => presets.some((p) => run(p, m) && run(p, m).flags))) return;
    const s = section("flags", "Dynamic keypoint flags", "Precision / recall against the ground-truth masks (moved objects: their recall after ';').");
    const rows = presets.map((p) => [p].concat(others.map((m) => {
      const f = run(p, m) && run(p, m).flags;
      return f ? num(f.precision) + " / " + num(f.recall) + (f.moved_object_recall > 0 ? "; " + num(f.moved_object_recall) : "") : "–";
    })));
    s.append(table(rows, ["sequence"].concat(others)));
  }

  // A sweep's cells: every repeat's ATE RMSE as a dot, the median as a bar (results.repeats).
  function distributionSection() {
    if (!results.repeats) return;
    const s = section("repeats", "ATE over repeats", "Each dot one run's ATE RMSE (cm), the bar the median the tables show; " +
      "runs done / failed per cell.");
    const cells = [];
    for (const p of presets) for (const m of modes) if (run(p, m)) cells.push(run(p, m));
    const all = [].concat(...cells.map((r) => r.ate_rmse_runs.map((v) => 100 * v)));
    if (!all.length) return;
    const NS = "http://www.w3.org/2000/svg", W = 940, rowH = 18, left = 330, right = 20;
    const H = 30 + rowH * cells.length, hi = Math.max(...all) * 1.05 || 1;
    const x = (v) => left + (W - left - right) * v / hi;
    const svg = document.createElementNS(NS, "svg");
    svg.setAttribute("width", W);
    svg.setAttribute("height", H);
    svg.setAttribute("id", "ate-repeats");
    const add = (name, attrs, text) => {
      const e = document.createElementNS(NS, name);
      for (const k in attrs) e.setAttribute(k, attrs[k]);
      if (text !== undefined) e.textContent = text;
      svg.append(e);
      return e;
    };
    cells.forEach((r, i) => {
      const y = 20 + rowH * i;
      add("text", {x: left - 8, y: y + 4, "text-anchor": "end", "font-size": 12},
          r.preset + " · " + r.mode + " (" + r.repeats + (r.failed ? " / " + r.failed + " failed" : "") + ")");
      add("line", {x1: left, x2: W - right, y1: y, y2: y, stroke: "#eee"});
      for (const v of r.ate_rmse_runs) add("circle", {cx: x(100 * v), cy: y, r: 3.5, fill: colourOf(r.mode), "fill-opacity": 0.7, class: "repeat"});
      if (r.ate_m) add("line", {x1: x(100 * r.ate_m.rmse), x2: x(100 * r.ate_m.rmse), y1: y - 7, y2: y + 7, stroke: "#000", "stroke-width": 2});
    });
    for (let k = 0; k <= 4; ++k) {
      const v = hi * k / 4;
      add("text", {x: x(v), y: H - 2, "text-anchor": "middle", "font-size": 11}, num(v, 2) + " cm");
    }
    s.append(el("div", {class: "wide"}, svg));
  }

  // Per preset: the ground truth and every mode's trajectory, aligned as the ATE aligns it.
  function trajectoryChart(parent, preset) {
    const T = data.trajectories[preset], id = "trajectory-" + preset;
    const drawn = modes.filter((m) => T.modes[m]);
    if (!T.gt_path || !drawn.length) return;
    const W = 440, H = 380, xs = T.gt_path.x.slice(), ys = T.gt_path.y.slice();
    for (const m of drawn) { xs.push(...T.modes[m].est.x); ys.push(...T.modes[m].est.y); }
    const [rx, ry] = equalRanges(xs, ys, W - 70, H - 60);
    const facets = [{scale: "x", auto: false}, {scale: "y", auto: false}];
    const series = [{}, {label: "ground truth", stroke: "#555", facets: facets,
                         paths: (u, i) => drawPolyline(u, i, () => "rgba(80, 80, 80, 0.6)", 2.5)}];
    const rows = [null, [T.gt_path.x, T.gt_path.y]];
    for (const m of drawn) {
      series.push({label: m, stroke: colourOf(m), facets: facets, paths: (u, i) => drawPolyline(u, i, () => colourOf(m), 1.5)});
      rows.push([T.modes[m].est.x, T.modes[m].est.y]);
    }
    const keep = (fixed) => (u, lo, hi) => (lo === null || hi === null ? fixed : [lo, hi]);
    const box = chartBox(parent, id, preset + " (top view x–y)");
    new uPlot({mode: 2, width: W, height: H, legend: {show: false},
               cursor: {drag: {x: true, y: true, uni: 20}, points: {show: false}, dataIdx: () => null},
               scales: {x: {time: false, range: keep(rx)}, y: {range: keep(ry)}},
               axes: [{label: "x (m)"}, {label: "y (m)"}], series: series}, rows, box);
    const legend = [el("span", {class: "swatch", style: "background:#555"}), "ground truth"];
    for (const m of drawn) {
      const r = run(preset, m);
      legend.push(" · ", el("span", {class: "swatch", style: "background:" + colourOf(m)}),
                  m + (r && r.ate_m ? " " + num(100 * r.ate_m.rmse, 2) + " cm" : ""));
    }
    box.append(el("div", {class: "legend"}, legend));
    for (const n of T.notes || []) box.append(el("div", {class: "note"}, n));
    charts.push(id);
  }
  function trajectorySection() {
    const s = section("trajectories", "Trajectories", "Every mode's estimate aligned onto the ground truth (grey) as the ATE aligns it. " +
      "Drag to zoom, double-click to reset.");
    const row = el("div", {class: "row"});
    s.append(row);
    for (const p of presets) if (data.trajectories[p]) trajectoryChart(row, p);
  }

  header();
  accuracySection();
  distributionSection();
  etaSection();
  timeSection();
  flagsSection();
  trajectorySection();
  window.lrdReport = {charts: charts.slice(), images: 0, samples: 0};
  window.lrdCommon.markReady(charts);
})();
