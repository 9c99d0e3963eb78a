// SPDX-License-Identifier: Apache-2.0
// Opens a 3D Tiles tileset in real viewers, CesiumJS and three.js with 3DTilesRendererJS, in
// headless Chromium (puppeteer-core), served from localhost, and checks what a user would see:
// the viewer loads it without an error, draws it (a share of the frame is not background), reaches
// the finest level when asked for small screen-space errors, asks for the root first and for every
// tile's parent too (coarse first, no level skipped, as streaming needs; the order of a parent and
// its child is the viewer's to choose when both are due in one frame, so it is not checked). CesiumJS must place the root where the tileset's own
// transform says, on the WGS 84 ellipsoid, within 1 cm, and near the data's centre.
// Prints "ok - ..." or "not ok - ..." a check; exits 1 if any failed, 77 if it cannot run here.
//
// Usage: node viewers.js MODULES TILESET.json [--viewer cesium|three]... [--sse PIXELS]
//          [--screenshots FOLDER] [--size WIDTHxHEIGHT] [--chromium PATH]
// MODULES: the folder whose node_modules hold puppeteer-core, cesium, three, 3d-tiles-renderer.
"use strict";
const fs = require("fs");
const http = require("http");
const path = require("path");
const { puppeteerOr77, withChromium, checks, newTab, patience } = require("./chromium.js");

const args = process.argv.slice(2);
const modules = path.resolve(args[0] || "", "node_modules");
const tilesetFile = path.resolve(args[1] || "");
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const viewers = args.flatMap((a, i) => (args[i - 1] === "--viewer" ? [a] : []));
if (viewers.length === 0) viewers.push("cesium", "three");
const sse = option("--sse", "16");
const screenshots = option("--screenshots", null);
const [width, height] = option("--size", "1024x768").split("x").map(Number);
const chromium = option("--chromium", "/usr/bin/chromium");

for (const needed of ["cesium", "three", "3d-tiles-renderer"]) {
  if (!fs.existsSync(path.join(modules, needed))) {
    console.log(`viewers.js: skipped: ${needed} is not installed in ${modules}`);
    process.exit(77);
  }
}
const puppeteer = puppeteerOr77(modules, chromium, "viewers.js");
const tally = checks(), check = tally.check;

// The tileset's tree: each content's URI, its parent's content URI (null at the root) and depth.
const tileset = JSON.parse(fs.readFileSync(tilesetFile, "utf8"));
const tiles = new Map();
(function walk(tile, parentUri, depth) {
  const uri = tile.content ? tile.content.uri : parentUri;
  if (tile.content) tiles.set(uri, { parent: parentUri, depth });
  for (const child of tile.children || []) walk(child, uri, depth + 1);
})(tileset.root, null, 0);
const deepest = Math.max(...[...tiles.values()].map((t) => t.depth));

// The server: pages from here, packages from MODULES, the tileset's folder under /tiles/.
const types = { ".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript",
  ".json": "application/json", ".glb": "model/gltf-binary", ".wasm": "application/wasm",
  ".css": "text/css", ".png": "image/png", ".svg": "image/svg+xml" };
const roots = { pages: __dirname, modules, tiles: path.dirname(tilesetFile) };
let requested = [];
const server = http.createServer((request, response) => {
  const url = decodeURIComponent(new URL(request.url, "http://localhost").pathname);
  const [, mount, ...rest] = url.split("/");
  const root = roots[mount];
  const file = root && path.resolve(root, rest.join("/"));
  if (!file || !file.startsWith(root + path.sep) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    response.writeHead(404).end();
    return;
  }
  response.writeHead(200, { "Content-Type": types[path.extname(file)] || "application/octet-stream" });
  fs.createReadStream(file).pipe(response);
});

// Geodetic longitude, latitude (degrees) and height of an ECEF point on WGS 84 (Bowring's
// iteration, converged to well under a millimetre).
function geodetic([x, y, z]) {
  const a = 6378137, f = 1 / 298.257223563, e2 = f * (2 - f);
  const p = Math.hypot(x, y);
  let lat = Math.atan2(z, p * (1 - e2)), h = 0;
  for (let i = 0; i < 10; i++) {
    const n = a / Math.sqrt(1 - e2 * Math.sin(lat) ** 2);
    h = p / Math.cos(lat) - n;
    lat = Math.atan2(z, p * (1 - e2 * n / (n + h)));
  }
  return [Math.atan2(y, x) * 180 / Math.PI, lat * 180 / Math.PI, h];
}
// Metres between two geodetic points close together.
function metresApart([lon1, lat1, h1], [lon2, lat2, h2]) {
  const r = 6378137, k = Math.PI / 180;
  const east = (lon2 - lon1) * k * r * Math.cos(lat1 * k), north = (lat2 - lat1) * k * r;
  return Math.hypot(east, north, h2 - h1);
}

async function open(browser, viewer, base) {
  requested = [];
  const page = await newTab(browser);
  await page.setViewport({ width, height });
  const problems = [];
  // The tiles in the order the page asked for them (the server sees them in whatever order its
  // connections deliver).
  const tilesPrefix = `${base}/tiles/`;
  page.on("request", (r) => {
    const url = r.url().split("?")[0];
    if (url.startsWith(tilesPrefix) && url.endsWith(".glb")) requested.push(decodeURIComponent(url.slice(tilesPrefix.length)));
  });
  page.on("pageerror", (e) => problems.push(String(e)));
  page.on("requestfailed", (r) => {
    if (new URL(r.url()).hostname === "127.0.0.1") problems.push(`request failed: ${r.url()}`);
  });
  const query = `tileset=/tiles/${encodeURIComponent(path.basename(tilesetFile))}&sse=${sse}`;
  await page.goto(`${base}/pages/${viewer}.html?${query}`);
  let state = { ready: false };
  const started = Date.now();
  while (!state.ready && !state.error && Date.now() - started < patience) {
    await new Promise((r) => setTimeout(r, 250));
    state = await page.evaluate(() => (window.viewerState ? window.viewerState() : { ready: false }));
  }
  check(`${viewer}: loads the tileset without an error`, state.ready && !state.error && problems.length === 0,
    state.error || problems[0] || `not done after ${patience / 1000} s`);
  if (!state.ready) return page.close();
  check(`${viewer}: draws it (${(100 * state.covered).toFixed(1)}% of the frame, ${state.tilesWithContent} tiles, ${state.trianglesDrawn} triangles)`,
    state.covered > 0.05 && state.trianglesDrawn > 0, "less than 5% of the frame");
  const depths = requested.map((uri) => (tiles.has(uri) ? tiles.get(uri).depth : -1));
  check(`${viewer}: asks only for the tileset's tiles`, depths.every((d) => d >= 0), requested.join(" "));
  check(`${viewer}: asks for the root first`, tiles.get(requested[0]) && tiles.get(requested[0]).parent === null, requested[0]);
  const orphan = requested.find((uri) => tiles.has(uri) && tiles.get(uri).parent !== null &&
    !requested.includes(tiles.get(uri).parent));
  check(`${viewer}: asks for every tile's parent too`, orphan === undefined, orphan);
  if (Number(sse) <= 1) {
    check(`${viewer}: reaches the finest level (depth ${deepest})`, depths.includes(deepest), `deepest asked: ${Math.max(...depths)}`);
    // Everything in view at the finest level, each part once: the viewer draws exactly the finest
    // level's triangles (no coarser tile left beside its children, none missing).
    const levels = tileset.extras && tileset.extras.lasmesh && tileset.extras.lasmesh.levels;
    if (levels) {
      const finest = levels[levels.length - 1].triangles;
      check(`${viewer}: draws the finest level's ${finest} triangles`, state.trianglesDrawn === finest, state.trianglesDrawn);
    }
  }
  if (state.centre) {
    const box = tileset.root.boundingVolume.box, m = tileset.root.transform;
    const ecef = [0, 1, 2].map((r) => m[r] * box[0] + m[4 + r] * box[1] + m[8 + r] * box[2] + m[12 + r]);
    const apart = metresApart(geodetic(ecef), state.centre);
    check(`${viewer}: places the root where its transform says (${(apart * 1000).toFixed(2)} mm apart)`, apart < 0.01, apart);
    // And near the data's centre, which lasmesh computed with PROJ (a transform written row by row
    // instead of column by column would put the root thousands of kilometres away).
    const said = tileset.extras && tileset.extras.lasmesh && tileset.extras.lasmesh.centre;
    if (said) {
      const away = metresApart([said[0], said[1], 0], [state.centre[0], state.centre[1], 0]);
      const halfDiagonal = Math.hypot(...box.slice(3));
      check(`${viewer}: near the data's centre (${away.toFixed(2)} m)`, away <= halfDiagonal, `${away} m`);
    }
  }
  if (screenshots) {
    fs.mkdirSync(screenshots, { recursive: true });
    await page.screenshot({ path: path.join(screenshots, `${viewer}.png`) });
  }
  await page.close();
}

(async () => {
  await new Promise((r) => server.listen(0, "127.0.0.1", r));
  const base = `http://127.0.0.1:${server.address().port}`;
  try {
    await withChromium(puppeteer, chromium, async (browser) => {
      for (const viewer of viewers) await open(browser, viewer, base);
    });
  } finally {
    server.close();
  }
  process.exit(tally.failures > 0 ? 1 : 0);
})().catch((e) => {
  console.log(`not ok - viewers.js: ${e && e.stack || e}`);
  process.exit(1);
});
