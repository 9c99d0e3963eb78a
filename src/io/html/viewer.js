// SPDX-License-Identifier: Apache-2.0
// The viewer inside lasmesh's .html pages (src/io/html_writer.hpp): it decodes the mesh the page
// holds and shows it with three.js, lit or in its flat colours, with orbit, pan and zoom, a
// measure tool (two clicks on the surface: the distance and dx, dy, dz in the file's units,
// snapped to a vertex when one is within a few pixels), a horizontal section, the run's facts, and
// with a heat map (lasmesh compare) each vertex's distance to the points on request. Served by
// `lasmesh view`, it also shows the controls that mesh again and save (live_controls.js).
// Bundled with three.js by esbuild when lasmesh is built (tools/bundle_viewer.sh).
import {
  BufferAttribute, BufferGeometry, Color, DirectionalLight, DoubleSide, HemisphereLight, Line,
  LineBasicMaterial, LinearSRGBColorSpace, Mesh, MeshBasicMaterial, MeshStandardMaterial, PerspectiveCamera,
  Plane, Raycaster, Scene, SphereGeometry, SRGBColorSpace, Vector2, Vector3, WebGLRenderer,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { MeshoptDecoder } from "three/addons/libs/meshopt_decoder.module.js";
import { fetchMesh, startLiveControls } from "./live_controls.js";

const api = { ready: false, error: null };
window.lasmesh = api;

const base64Bytes = (id) => {
  const text = atob(document.getElementById(id).textContent.trim());
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  return bytes;
};
const inflate = async (bytes) =>
  new Uint8Array(await new Response(new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"))).arrayBuffer());

// The page's mesh (zlib-compressed bytes): header, integer positions, sRGB colours, normals, triangles.
async function readMesh(compressed) {
  const data = await inflate(compressed);
  const view = new DataView(data.buffer);
  if (new TextDecoder().decode(data.subarray(0, 4)) !== "LMSH" || view.getUint32(4, true) !== 1)
    throw new Error("the page's mesh data is not lasmesh's version 1");
  const headerLength = view.getUint32(8, true);
  const header = JSON.parse(new TextDecoder().decode(data.subarray(12, 12 + headerLength)));
  const start = Math.ceil((12 + headerLength) / 4) * 4;
  const part = (name) => {
    const b = header.buffers[name];
    return b ? data.subarray(start + b.offset, start + b.offset + b.length) : null;
  };
  await MeshoptDecoder.ready;
  const n = header.vertices;
  const decode = (name, size, Type) => {
    const source = part(name);
    if (!source) return null;
    const out = new Type((n * size) / Type.BYTES_PER_ELEMENT);
    MeshoptDecoder.decodeVertexBuffer(new Uint8Array(out.buffer), n, size, source);
    return out;
  };
  const quantized = decode("positions", 12, Int32Array); // x, y, z
  const colors = decode("colors", 4, Uint8Array); // r, g, b, 255
  const normals = decode("normals", 4, Int8Array); // x, y, z, 0
  const heatColors = decode("heat_colors", 4, Uint8Array); // r, g, b, 255 on the heat ramp
  const heatDistance = decode("heat_distance", 4, Float32Array); // to the nearest point
  const indices = new Uint32Array(3 * header.triangles);
  MeshoptDecoder.decodeIndexBuffer(new Uint8Array(indices.buffer), indices.length, 4, part("indices"));
  // Lighter copies on the same vertices, each a quarter of the one before: drawn while the camera
  // moves when the whole mesh cannot keep up.
  const motion = (header.motion || []).map(({ buffer, triangles }) => {
    const level = new Uint32Array(3 * triangles);
    MeshoptDecoder.decodeIndexBuffer(new Uint8Array(level.buffer), level.length, 4, part(buffer));
    return level;
  });
  return { header, quantized, colors, normals, indices, motion, heatColors, heatDistance };
}

// sRGB bytes to linear values (IEC 61966-2-1), as three.js expects vertex colours.
const linear = new Float32Array(256).map((_, i) => {
  const c = i / 255;
  return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
});

// sRGB bytes (r, g, b, a a vertex) as three.js's linear colour attribute, or (`asIs`) the sRGB
// values themselves.
function colorAttribute(bytes, n, asIs = false) {
  const c = new Float32Array(3 * n);
  for (let v = 0; v < n; v++) for (let k = 0; k < 3; k++) c[3 * v + k] = asIs ? bytes[4 * v + k] / 255 : linear[bytes[4 * v + k]];
  return new BufferAttribute(c, 3);
}

function geometryOf({ header, quantized, colors, normals, indices }) {
  const n = header.vertices, step = header.step;
  const positions = new Float32Array(3 * n);
  for (let i = 0; i < 3 * n; i++) positions[i] = quantized[i] * step;
  const geometry = new BufferGeometry();
  geometry.setAttribute("position", new BufferAttribute(positions, 3));
  geometry.setIndex(new BufferAttribute(indices, 1));
  if (colors) geometry.setAttribute("color", colorAttribute(colors, n));
  if (normals) {
    const m = new Float32Array(3 * n);
    for (let v = 0; v < n; v++) for (let k = 0; k < 3; k++) m[3 * v + k] = normals[4 * v + k] / 127;
    geometry.setAttribute("normal", new BufferAttribute(m, 3));
  } else {
    geometry.computeVertexNormals();
  }
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  return geometry;
}

const unitOf = (facts) => {
  if (facts && facts.crs && facts.crs.unit) return facts.crs.unit;
  const summary = facts && facts.crs && facts.crs.summary;
  const match = summary && /, in ([^,]+)$/.exec(summary);
  return match ? match[1] : "units";
};

function fill(id, rows) {
  const table = document.getElementById(id);
  table.replaceChildren();
  for (const [name, value] of rows) {
    if (value === undefined || value === null || value === "") continue;
    const row = table.insertRow();
    row.insertCell().textContent = name;
    row.insertCell().textContent = value;
  }
}

async function main() {
  const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  const background = new Color("#dde4ea");
  renderer.setClearColor(background);
  renderer.localClippingEnabled = true;
  document.body.appendChild(renderer.domElement);

  const scene = new Scene();
  const section = new Plane(new Vector3(0, 0, -1), 0);
  const lit = new MeshStandardMaterial({ roughness: 1, metalness: 0, side: DoubleSide });
  const flat = new MeshBasicMaterial({ side: DoubleSide });
  const mesh = new Mesh(new BufferGeometry(), lit);
  scene.add(mesh);
  const sky = new HemisphereLight(0xffffff, 0x707070, 1.6);
  sky.position.set(0, 0, 1);
  scene.add(sky);
  const camera = new PerspectiveCamera(45, window.innerWidth / window.innerHeight, 0.001, 1000);
  camera.up.set(0, 0, 1);
  const sun = new DirectionalLight(0xffffff, 1.4);
  sun.position.set(0.4, 0.6, 1);
  camera.add(sun);
  scene.add(camera);
  const controls = new OrbitControls(camera, renderer.domElement);
  const render = () => renderer.render(scene, camera);

  // What the mesh shown sets: replaced by show() when `lasmesh view` sends another.
  let decoded, header, unit = "units", number = (x) => x.toFixed(3);
  let geometry = mesh.geometry, box, sphere, radius = 1, own = null, heat = null, hasColors = false;
  let heatOn = false;

  // Moving the camera. While the user drags, wheels or orbits, each frame is drawn at the next
  // animation frame, in the first of these ways that keeps the frames coming at 55 a second or
  // more: the whole mesh at the screen's resolution, at half of it (a quarter of the pixels), then
  // the mesh's lighter copies at half resolution, each a quarter of the one before, the lightest
  // last at a quarter. A way measured slower is not used again for this mesh (nextWay). A quarter
  // of a second after the last move the whole mesh is drawn at full resolution; picking,
  // measuring and pictures always use it. Interactive level of detail, as VTK's and ParaView's
  // desktop viewers do it.
  let levels = [], ways = [], way = 0, dragging = false;
  let budget = 1000 / 55, budgetSet = false, period = 1000 / 30; // ms; period: the display's, measured (at most 1/30 s)
  let frameRequest = 0, frameWanted = false, lastMove = 0, lastFrame = 0, lastTick = 0, times = [];
  const drawLevel = (k, scale = 1) => {
    if (geometry.index !== levels[k]) geometry.setIndex(levels[k]);
    if (renderer.getPixelRatio() !== window.devicePixelRatio * scale) renderer.setPixelRatio(window.devicePixelRatio * scale);
    render();
  };
  const still = () => {
    cancelAnimationFrame(frameRequest);
    frameRequest = 0, frameWanted = false, lastFrame = 0, lastTick = 0;
    drawLevel(0);
  };
  const median = (xs) => {
    const s = [...xs].sort((a, b) => a - b), m = s.length >> 1;
    return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
  };
  // The way after `from`, given the intervals of frames drawn back to back in it (the first left
  // out: it may upload the way's indices) and the longest a frame may take: their median, of 4
  // or more, above the limit steps to the next way; of 3 or more, above four times the limit,
  // skips to the first way whose triangles the limit allows at the rate measured (the lightest
  // if none does). A median, so that one stall (a shader compiled, a tab shown again) does not count.
  const nextWay = (from, intervals, limit) => {
    const counted = intervals.slice(1);
    if (from + 1 >= ways.length || counted.length < 3) return from;
    const typical = median(counted);
    if (typical > 4 * limit) {
      const allowed = (levels[ways[from].level].count * limit) / typical;
      const fit = ways.findIndex((w, k) => k > from && levels[w.level].count <= allowed);
      return fit < 0 ? ways.length - 1 : fit;
    }
    return counted.length >= 4 && typical > limit ? from + 1 : from;
  };
  // Each animation frame while moving: draws what moved since the last, or once still, the whole
  // mesh. Judged here, not by a timer: a frame slower than the wait would end every move. Ticks
  // with nothing to draw measure the display's own period: a display paced under 55 a second
  // (30 in a power-saving mode) is not taken for a slow renderer.
  const nextFrame = (now) => {
    frameRequest = 0;
    if (frameWanted) {
      if (lastFrame) times.push(now - lastFrame); // the frame before was drawn: this one's interval is its cost
      const next = nextWay(way, times, budgetSet ? budget : Math.max(budget, 1.1 * period));
      if (next !== way) (way = next), updateMoving(), (times = []);
      else if (times.length > 8) times = [];
      frameWanted = false;
      lastFrame = now;
      drawLevel(ways[way].level, ways[way].scale);
    } else {
      if (lastTick && !lastFrame) period = Math.min(period, now - lastTick);
      if (performance.now() - lastMove > 250) return still();
      lastFrame = 0;
    }
    lastTick = now;
    frameRequest = requestAnimationFrame(nextFrame);
  };
  const moved = () => {
    lastMove = performance.now();
    frameWanted = true;
    if (!frameRequest) (times = []), (frameRequest = requestAnimationFrame(nextFrame));
  };
  controls.addEventListener("start", () => { dragging = true; });
  controls.addEventListener("end", () => { dragging = false; });
  controls.addEventListener("change", () => (dragging || frameRequest ? moved() : drawLevel(0)));
  const updateMoving = () => {
    const { level, scale } = ways[way];
    document.getElementById("moving").textContent = (level > 0 ? `${(levels[level].count / 3).toLocaleString("en")} triangles`
      : "the whole mesh") + (scale < 1 ? `, at 1/${1 / scale} of the resolution` : "");
    api.moving = { triangles: levels[level].count / 3, scale };
  };

  // Views: oblique from the south-west, or from above through a long lens (nearly orthographic:
  // what is seen is the plan).
  const look = (direction, fov) => {
    camera.fov = fov;
    const distance = radius / Math.sin((fov * Math.PI) / 360) * 1.05;
    camera.position.copy(sphere.center).addScaledVector(direction.clone().normalize(), distance);
    camera.near = distance / 1000;
    camera.far = distance + radius * 4;
    camera.updateProjectionMatrix();
    controls.target.copy(sphere.center);
    controls.update();
    render();
  };
  const obliqueView = () => look(new Vector3(-0.55, -0.85, 0.75), 45);
  const topView = () => look(new Vector3(0, -1e-4, 1), 8);

  // Section: everything above a horizontal plane is cut away.
  const sectionBox = document.getElementById("section"), sectionHeight = document.getElementById("section-height");
  const applySection = () => {
    section.constant = Number(sectionHeight.value);
    const planes = sectionBox.checked ? [section] : [];
    lit.clippingPlanes = planes;
    flat.clippingPlanes = planes;
    lit.needsUpdate = flat.needsUpdate = true;
    document.getElementById("section-value").textContent = sectionBox.checked
      ? `z ${number(section.constant + header.origin[2])} ${unit}` : "";
    render();
  };
  sectionBox.addEventListener("change", applySection);
  sectionHeight.addEventListener("input", applySection);

  // The heat map: the vertices coloured by their distance to the points instead. Its colours are
  // blended between vertices as sRGB values, as the heat-map PLY shows in other viewers and as the
  // legend's ramp is drawn: the frame is then written without sRGB encoding (blending a rainbow
  // in linear light would brighten it between the vertices).
  const paint = () => {
    const on = heatOn && !!heat;
    renderer.outputColorSpace = on ? LinearSRGBColorSpace : SRGBColorSpace;
    // The same background either way: without encoding, its sRGB values are given as they are.
    renderer.setClearColor(on ? new Color().setRGB(0xdd / 255, 0xe4 / 255, 0xea / 255, LinearSRGBColorSpace) : background);
    if (on || own) geometry.setAttribute("color", on ? heat : own);
    else geometry.deleteAttribute("color");
    lit.vertexColors = flat.vertexColors = on || hasColors;
    lit.color.set(on || hasColors ? 0xffffff : 0xb4b4b4);
    flat.color.set(on || hasColors ? 0xffffff : 0xb4b4b4);
    lit.needsUpdate = flat.needsUpdate = true;
    document.getElementById("heat").checked = on;
    document.getElementById("heat-legend").hidden = !on;
    render();
  };
  const setHeat = (on) => {
    if (!heat) return;
    heatOn = on;
    paint();
  };
  document.getElementById("heat").addEventListener("change", (e) => setHeat(e.target.checked));

  const setFlat = (on) => {
    mesh.material = on ? flat : lit;
    document.getElementById("flat").checked = on;
    render();
  };
  document.getElementById("flat").addEventListener("change", (e) => setFlat(e.target.checked));
  document.getElementById("top").addEventListener("click", topView);
  document.getElementById("reset").addEventListener("click", obliqueView);

  // Measuring: a click (not a drag) on the surface picks a point; a vertex of the hit triangle
  // within 8 pixels is taken instead (a point the file holds). Points are in the file's
  // coordinates: the origin plus the integer times the step, in doubles.
  const measureBox = document.getElementById("measure");
  const markers = [];
  let markerGeometry = new SphereGeometry(1, 16, 8);
  const markerMaterial = new MeshBasicMaterial({ color: 0xe0115f, depthTest: false });
  const lineMaterial = new LineBasicMaterial({ color: 0xe0115f, depthTest: false });
  let picked = [], line = null;
  const fileCoordinates = (vertex) => [0, 1, 2].map((k) => header.origin[k] + decoded.quantized[3 * vertex + k] * header.step);
  const screenOf = (local) => {
    const p = new Vector3(...local).project(camera);
    const rect = renderer.domElement.getBoundingClientRect();
    return [rect.left + ((p.x + 1) / 2) * rect.width, rect.top + ((1 - p.y) / 2) * rect.height];
  };
  const showMeasurement = () => {
    const out = document.getElementById("measurement");
    const rows = picked.map((p, i) => [i ? "B" : "A", p.file.map(number).join(" ") + (p.vertex === null ? ""
      : decoded.heatDistance ? ` (vertex, ${number(decoded.heatDistance[p.vertex])} ${unit} from the points)` : " (vertex)")]);
    if (picked.length === 2) {
      const d = [0, 1, 2].map((k) => picked[1].file[k] - picked[0].file[k]);
      api.measurement = { points: picked.map((p) => p.file), distance: Math.hypot(...d), delta: d };
      rows.push(["distance", `${number(Math.hypot(...d))} ${unit}`],
        ["dx dy dz", `${d.map(number).join(" ")} ${unit}`]);
    }
    fill("measurement", rows);
    out.hidden = picked.length === 0;
  };
  const clearMeasurement = () => {
    picked = [];
    for (const m of markers.splice(0)) scene.remove(m);
    if (line) scene.remove(line), (line = null);
    api.measurement = null;
    showMeasurement();
  };
  const pick = (clientX, clientY) => {
    if (frameRequest || geometry.index !== levels[0]) still(); // a click that moved the camera a pixel: the whole mesh
    const rect = renderer.domElement.getBoundingClientRect();
    const ndc = new Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const raycaster = new Raycaster();
    raycaster.setFromCamera(ndc, camera);
    const hit = raycaster.intersectObject(mesh).find((h) => !sectionBox.checked || h.point.z <= section.constant);
    if (!hit) return;
    let vertex = null, best = 8;
    for (const v of [hit.face.a, hit.face.b, hit.face.c]) {
      const local = [0, 1, 2].map((k) => geometry.attributes.position.array[3 * v + k]);
      const [x, y] = screenOf(local);
      const away = Math.hypot(x - clientX, y - clientY);
      if (away <= best) best = away, vertex = v;
    }
    const local = vertex !== null ? [0, 1, 2].map((k) => geometry.attributes.position.array[3 * vertex + k]) : hit.point.toArray();
    const file = vertex !== null ? fileCoordinates(vertex) : local.map((x, k) => x + header.origin[k]);
    if (picked.length === 2) clearMeasurement();
    picked.push({ file, vertex, local });
    const marker = new Mesh(markerGeometry, markerMaterial);
    marker.position.set(...local);
    marker.renderOrder = 2;
    markers.push(marker);
    scene.add(marker);
    if (picked.length === 2) {
      line = new Line(new BufferGeometry().setFromPoints(picked.map((p) => new Vector3(...p.local))), lineMaterial);
      line.renderOrder = 1;
      scene.add(line);
    }
    showMeasurement();
    render();
  };
  let down = null;
  renderer.domElement.addEventListener("pointerdown", (e) => { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener("pointerup", (e) => {
    if (measureBox.checked && down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) pick(e.clientX, e.clientY);
    down = null;
  });
  measureBox.addEventListener("change", () => {
    renderer.domElement.style.cursor = measureBox.checked ? "crosshair" : "";
  });

  window.addEventListener("resize", () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    render();
  });

  // Shows a decoded mesh: the first, or (keepView) another of the same data from `lasmesh view`.
  const show = (next, keepView) => {
    decoded = next;
    header = decoded.header;
    const facts = header.facts || {};
    unit = unitOf(facts);
    const decimals = Math.max(3, Math.ceil(-Math.log10((header.cell_size || 1) / 100)));
    number = (x) => x.toFixed(decimals);
    document.title = `${header.name} (lasmesh)`;
    document.getElementById("name").textContent = header.name;
    fill("facts", [
      ["triangles", header.triangles.toLocaleString("en")],
      ["vertices", header.vertices.toLocaleString("en")],
      ["cell", header.cell_size ? `${number(header.cell_size)} ${unit}` : ""],
      ["points", facts.points_read !== undefined ? facts.points_read.toLocaleString("en") : ""],
      ["iso", facts.iso !== undefined ? `${facts.iso} ${facts.iso === 1 ? "point" : "points"} per cell` : ""],
      ["simplify bound", facts.simplify && facts.simplify.error ? `${number(facts.simplify.error)} ${unit}` : ""],
      ["CRS", (facts.crs && facts.crs.summary) || header.crs || "none declared"],
      ["origin", header.origin.map((x) => x.toFixed(3)).join(" ")],
    ]);
    document.getElementById("triangles").textContent = String(header.triangles);

    clearMeasurement();
    cancelAnimationFrame(frameRequest), (frameRequest = 0), (frameWanted = false);
    geometry.setIndex(levels[0] || geometry.index); // its own, so that dispose() frees it
    geometry.dispose();
    geometry = geometryOf(decoded);
    mesh.geometry = geometry;
    levels = [geometry.index, ...decoded.motion.map((m) => new BufferAttribute(m, 1))];
    ways = [{ level: 0, scale: 1 }, ...levels.map((_, k) => ({ level: k, scale: 0.5 })),
      { level: levels.length - 1, scale: 0.25 }];
    way = 0;
    if (renderer.getPixelRatio() !== window.devicePixelRatio) renderer.setPixelRatio(window.devicePixelRatio);
    updateMoving();
    hasColors = !!decoded.colors;
    own = geometry.getAttribute("color") || null;
    heat = decoded.heatColors ? colorAttribute(decoded.heatColors, header.vertices, true) : null;
    box = geometry.boundingBox, sphere = geometry.boundingSphere;
    radius = Math.max(sphere.radius, 1e-6);
    markerGeometry.dispose();
    markerGeometry = new SphereGeometry(radius / 150, 16, 8);

    sectionHeight.min = box.min.z;
    sectionHeight.max = box.max.z;
    sectionHeight.step = (box.max.z - box.min.z) / 200 || 1;
    if (!keepView) sectionHeight.value = (box.min.z + box.max.z) / 2;

    document.getElementById("heat-choice").hidden = !heat;
    const legend = document.getElementById("heat-legend");
    legend.replaceChildren();
    if (heat) {
      const s = header.heat_scale, ramp = document.createElement("span");
      ramp.className = "ramp";
      legend.append("0 ", ramp, ` ${number(s)} ${unit} and beyond`, document.createElement("br"),
        `blue 0, cyan ${number(s / 4)}, green ${number(s / 2)}, yellow ${number((3 * s) / 4)}, red ${number(s)}`);
    }
    paint();
    applySection();
    if (!keepView) obliqueView();
    else render();
    Object.assign(api, { triangles: header.triangles, vertices: header.vertices, header });
  };

  // A page written to a file holds its mesh; `lasmesh view`'s page fetches it, showing progress.
  const live = document.getElementById("lasmesh-live");
  const liveSettings = live ? JSON.parse(live.textContent) : null;
  const held = document.getElementById("lasmesh-mesh").textContent.trim() !== "";
  show(await readMesh(held ? base64Bytes("lasmesh-mesh") : await fetchMesh(liveSettings.token,
    document.getElementById("name"))), false);
  Object.assign(api, {
    // Where a point in the file's coordinates is on the screen (CSS pixels).
    screenOfFile: (p) => screenOf(p.map((x, k) => x - header.origin[k])),
    vertexInFile: fileCoordinates,
    setFlat, setHeat, topView, obliqueView, measurement: null,
    // Turns the camera about the vertical through its target, as a drag does: the frame is drawn
    // at the next animation frame, from the level that keeps up (benchmarks orbit with it).
    orbitBy: (radians) => {
      camera.position.sub(controls.target).applyAxisAngle(new Vector3(0, 0, 1), radians).add(controls.target);
      dragging = true;
      controls.update();
      dragging = false;
    },
    // Draws the whole mesh now (after orbitBy, for a picture or a benchmark of the whole mesh).
    drawStill: still,
    // How moving draws: `moving` ({triangles, scale}) says, movingWays() lists the ways in order
    // ({level: 0 the whole mesh, 1, 2, ... the lighter copies; scale of the resolution}), and
    // setMovingWay(k) chooses one (tests; the page finds it from its frames).
    setMovingWay: (k) => ((way = Math.min(Math.max(k, 0), ways.length - 1)), updateMoving()),
    // The longest a frame may take while moving, in ms (18, or 1.1 display periods if longer,
    // unless set: tests set 0 or Infinity), and the way nextWay() would take from the whole mesh
    // given frame intervals (a test of the choice alone).
    setMovingBudget: (ms) => ((budget = ms), (budgetSet = true), (times = [])),
    wayAfter: (intervals, ms) => nextWay(0, intervals, ms),
    movingWays: () => ways.map(({ level, scale }) => ({ level, triangles: levels[level].count / 3, scale })),
    trianglesDrawn: () => geometry.index.count / 3,
    picked: () => picked.map((p) => p.file),
    canvas: renderer.domElement,
  });
  // The display's frame period, from a dozen animation frames with nothing drawn.
  let lastSample = 0, samples = 0;
  const sample = (now) => {
    if (lastSample) period = Math.min(period, now - lastSample);
    lastSample = now;
    if (++samples < 12) requestAnimationFrame(sample);
  };
  requestAnimationFrame(sample);
  // Served by `lasmesh view`: the controls that mesh again and save.
  if (live) startLiveControls(liveSettings, async (bytes) => show(await readMesh(bytes), true), api);
  api.ready = true;
}

main().catch((e) => {
  api.error = String((e && e.stack) || e);
  document.getElementById("name").textContent = `cannot show the mesh: ${e && e.message}`;
});
