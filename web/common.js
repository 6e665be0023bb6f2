// Helpers of the report pages (docs/report.md): the run page (report.js) and the benchmark page
// (benchmark.js) are drawn with these and uPlot, all inlined into one HTML file.
window.lrdCommon = (function () {
  "use strict";
  function el(tag, attrs, children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const c of [].concat(children || [])) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
    return e;
  }
  function num(v, digits) {
    if (v === undefined || v === null || Number.isNaN(v)) return "–";
    return typeof v === "number" ? (Number.isInteger(v) ? String(v) : v.toFixed(digits === undefined ? 3 : digits)) : String(v);
  }
  function section(root, id, title, intro) {
    const s = el("section", {id: id}, [el("h2", {}, title)]);
    if (intro) s.append(el("p", {class: "intro"}, intro));
    root.append(s);
    return s;
  }
  // Without `head` the first column is a row header.
  function table(rows, head) {
    const t = el("table");
    if (head) t.append(el("tr", {}, head.map((h) => el("th", {}, h))));
    for (const r of rows) t.append(el("tr", {}, r.map((c, i) => el(i === 0 && !head ? "th" : "td", {}, c))));
    return t;
  }
  function chartBox(parent, id, caption) {
    const box = el("figure", {class: "chart", id: id});
    parent.append(box);
    if (caption) box.append(el("figcaption", {}, caption));
    return box;
  }
  // Error → colour, from blue (0) through green and yellow to red (the largest error).
  function ramp(f) {
    const stops = [[49, 54, 149], [69, 117, 180], [116, 173, 209], [171, 221, 164], [254, 224, 139],
                   [244, 109, 67], [215, 48, 39]];
    const x = Math.min(Math.max(f, 0), 1) * (stops.length - 1), i = Math.min(Math.floor(x), stops.length - 2);
    const a = stops[i], b = stops[i + 1], w = x - i;
    return "rgb(" + a.map((c, k) => Math.round(c + (b[k] - c) * w)).join(",") + ")";
  }
  // Equal metres per pixel on both axes, so that a turn looks like a turn.
  function equalRanges(xs, ys, width, height) {
    let x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
    const per = Math.max((x1 - x0) / width, (y1 - y0) / height, 1e-4) * 1.1;
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    return [[cx - per * width / 2, cx + per * width / 2], [cy - per * height / 2, cy + per * height / 2]];
  }
  // A uPlot `paths` callback for mode 2 (x-y) series: a polyline with a colour per segment.
  function drawPolyline(u, seriesIdx, colourOf, width) {
    uPlot.orient(u, seriesIdx, (series, dx, dy, sx, sy, valToPosX, valToPosY, xOff, yOff, xDim, yDim) => {
      const ctx = u.ctx;
      ctx.save();
      ctx.lineWidth = (width || 2) * uPlot.pxRatio;
      for (let i = 1; i < dx.length; i++) {
        ctx.strokeStyle = colourOf(i);
        ctx.beginPath();
        ctx.moveTo(valToPosX(dx[i - 1], sx, xDim, xOff), valToPosY(dy[i - 1], sy, yDim, yOff));
        ctx.lineTo(valToPosX(dx[i], sx, xDim, xOff), valToPosY(dy[i], sy, yDim, yOff));
        ctx.stroke();
      }
      ctx.restore();
    });
    return null;
  }
  // Once images are decoded and uPlot has sized its plots (after a tick): where each figure landed
  // (page pixels, for the browser test's screenshot checks) and data-report-ready on <body>.
  function markReady(charts) {
    document.body.setAttribute("data-charts", charts.join(" "));
    window.addEventListener("load", () => setTimeout(() => {
      for (const fig of document.querySelectorAll("figure")) {
        const r = fig.getBoundingClientRect();
        fig.setAttribute("data-box", [r.left + window.scrollX, r.top + window.scrollY, r.width, r.height].map(Math.round).join(","));
      }
      document.body.setAttribute("data-report-ready", "true");
    }, 100));
  }
  return {el, num, section, table, chartBox, ramp, equalRanges, drawPolyline, markReady};
})();
