// The 3-D map of the run page (docs/report.md): the dense map, the sparse map's points and the
// keyframes drawn with three.js (inlined before this script when the run wrote a map), from three
// viewpoints; drag to orbit, wheel to zoom, right-drag to pan.
// Data: src/lrd/report/map_view_data.cc.
window.lrdMap3d = (function () {
  "use strict";
  const {el} = window.lrdCommon;

  function bytes(b64) {
    const s = atob(b64), out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  function cloud(c, fallbackColour, size) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(bytes(c.positions).buffer), 3));
    const material = new THREE.PointsMaterial({size: size, sizeAttenuation: false});
    if (c.colours) {
      geometry.setAttribute("color", new THREE.BufferAttribute(bytes(c.colours), 3, true));
      material.vertexColors = true;
    } else {
      material.color = new THREE.Color(fallbackColour);
    }
    return new THREE.Points(geometry, material);
  }
  function keyframePath(k) {
    const points = k.x.map((x, i) => new THREE.Vector3(x, k.y[i], k.z[i]));
    const group = new THREE.Group();
    group.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(points), new THREE.LineBasicMaterial({color: 0xdc322f})));
    group.add(new THREE.Points(new THREE.BufferGeometry().setFromPoints(points),
                               new THREE.PointsMaterial({color: 0xdc322f, size: 6, sizeAttenuation: false})));
    return group;
  }
  // Centre and size of the bulk of the points (2nd-98th percentile per axis: a few stray points far
  // away do not shrink the map to a dot).
  function extent(position) {
    const n = position.count, axes = [[], [], []], step = Math.max(1, Math.floor(n / 20000));
    for (let i = 0; i < n; i += step) { axes[0].push(position.getX(i)); axes[1].push(position.getY(i)); axes[2].push(position.getZ(i)); }
    const lo = [], hi = [];
    for (const a of axes) {
      a.sort((p, q) => p - q);
      lo.push(a[Math.floor(0.02 * (a.length - 1))]); hi.push(a[Math.ceil(0.98 * (a.length - 1))]);
    }
    const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
    return {centre: centre, size: Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.5)};
  }
  // The map is in the first camera's frame (x right, y down, z forward): the views put -y up.
  const VIEWS = [["map3d-oblique", "Oblique view", [0.8, -0.9, -1.1]], ["map3d-top", "Top view (from above)", [0, -1, -0.001]],
                 ["map3d-side", "Side view (from the left)", [-1, -0.15, 0]]];

  function view(parent, scene, box, id, title, direction, register) {
    const W = 460, H = 340;
    const fig = el("figure", {class: "chart map3d", id: id}, [el("figcaption", {}, title)]);
    parent.append(fig);
    const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    renderer.setPixelRatio(1);
    renderer.setSize(W, H);
    fig.append(renderer.domElement);
    const camera = new THREE.PerspectiveCamera(45, W / H, box.size / 1000, box.size * 100);
    camera.up.set(0, -1, 0);
    const d = new THREE.Vector3(...direction).normalize().multiplyScalar(1.7 * box.size);
    camera.position.copy(box.centre).add(d);
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(box.centre);
    controls.update();
    const render = () => renderer.render(scene, camera);
    controls.addEventListener("change", render);
    render();
    register(id, {render: render});
    return render;
  }

  return function mapSection(section, map, register) {
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xffffff);
    const layers = {};
    if (map.dense) scene.add(layers.dense = cloud(map.dense, 0x888888, 2));
    if (map.sparse) scene.add(layers.sparse = cloud(map.sparse, 0x073642, 3));
    if (map.keyframes && map.keyframes.x.length) scene.add(layers.keyframes = keyframePath(map.keyframes));
    const bulk = (layers.dense || layers.sparse);
    if (!bulk || bulk.geometry.getAttribute("position").count === 0) {
      section.append(el("p", {class: "note"}, "The map has no points."));
      return;
    }
    const box = extent(bulk.geometry.getAttribute("position"));
    const row = el("div", {class: "row"});
    const toggles = el("p", {class: "legend"});
    section.append(toggles, row);
    const renders = [];
    try {
      for (const [id, title, direction] of VIEWS) renders.push(view(row, scene, box, id, title, direction, register));
    } catch (e) {  // no WebGL in this browser: say so instead of a blank box
      row.replaceChildren(el("p", {class: "note"}, "This browser cannot draw WebGL: " + e.message));
      return;
    }
    const names = {dense: "dense map (" + (map.dense ? map.dense.count + " of " + map.dense.of : 0) + " points)",
                   sparse: "sparse map (" + (map.sparse ? map.sparse.count : 0) + " points)",
                   keyframes: "keyframes (" + map.keyframes.x.length + ", red)"};
    for (const [name, object] of Object.entries(layers)) {
      const box = el("input", {type: "checkbox", checked: "checked"});
      box.addEventListener("change", () => { object.visible = box.checked; renders.forEach((r) => r()); });
      toggles.append(el("label", {}, [box, " " + names[name]]), "  ");
    }
  };
})();
