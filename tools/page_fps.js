// SPDX-License-Identifier: Apache-2.0
// Frame rate of a lasmesh .html page while orbiting, in headless Chromium (puppeteer-core):
// - paced: the camera turns a step every animation frame, as a user's drag does, for 3 s (while
//   the page finds how to draw while moving: `moving` says how it drew, triangles and resolution)
//   and then for 5 s: frames drawn per second (the browser paces at most at the display's rate,
//   60 here);
// - unpaced: 30 frames of the whole mesh drawn back to back at full resolution, each waited for
//   (a pixel read back): what the renderer could do with it without the pacing.
// Prints one JSON line. Usage: node page_fps.js MODULES PAGE.html [--gpu] [--chromium PATH]
// --gpu: Chromium's hardware GL (EGL) instead of SwiftShader's software rendering.
"use strict";
const path = require("path");
const { puppeteerOr77 } = require("../tests/browser/chromium.js");

const args = process.argv.slice(2);
const modules = path.resolve(args[0] || "", "node_modules");
const page = path.resolve(args[1] || "");
const chromium = args.includes("--chromium") ? args[args.indexOf("--chromium") + 1] : "/usr/bin/chromium";
const puppeteer = puppeteerOr77(modules, chromium, "page_fps.js");

(async () => {
  const gl = args.includes("--gpu") ? ["--use-gl=egl", "--ignore-gpu-blocklist", "--enable-gpu"]
    : ["--use-angle=swiftshader", "--enable-unsafe-swiftshader"];
  const browser = await puppeteer.launch({ executablePath: chromium, headless: true,
    args: ["--no-sandbox", "--no-first-run", "--disable-background-networking", "--disable-dev-shm-usage", ...gl] });
  try {
    const tab = await browser.newPage();
    await tab.setViewport({ width: 1280, height: 800 });
    await tab.goto(`file://${page}`);
    await tab.waitForFunction(() => window.lasmesh && (window.lasmesh.ready || window.lasmesh.error), { timeout: 600000 });
    const result = await tab.evaluate(async () => {
      const api = window.lasmesh;
      if (api.error) return { error: api.error };
      const gl = api.canvas.getContext("webgl2");
      const renderer = gl.getParameter(gl.RENDERER);
      const pixel = new Uint8Array(4);
      const drawn = () => gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); // waits for the frame
      for (let i = 0; i < 5; i++) api.orbitBy(0.01), api.drawStill(), drawn(); // shaders compiled, buffers uploaded
      const orbit = (seconds) => new Promise((done) => {
        let frames = 0;
        const start = performance.now();
        const step = () => {
          api.orbitBy((2 * Math.PI) / 300);
          frames++;
          if (performance.now() - start < 1000 * seconds) requestAnimationFrame(step);
          else done((frames * 1000) / (performance.now() - start));
        };
        requestAnimationFrame(step);
      });
      const settling = await orbit(3); // the page finds how to draw while moving
      const paced = await orbit(5);
      const moving = api.moving;
      const t0 = performance.now();
      for (let i = 0; i < 30; i++) api.orbitBy((2 * Math.PI) / 30), api.drawStill(), drawn();
      const unpaced = 30000 / (performance.now() - t0);
      return { triangles: api.triangles, renderer, first_3s_fps: +settling.toFixed(1), paced_fps: +paced.toFixed(1), moving, whole_mesh_unpaced_fps: +unpaced.toFixed(1) };
    });
    console.log(JSON.stringify(result));
    process.exit(result.error ? 1 : 0);
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error(`page_fps.js: ${e && e.stack}`);
  process.exit(1);
});
