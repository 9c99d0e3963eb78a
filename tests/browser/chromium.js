// SPDX-License-Identifier: Apache-2.0
// What the browser tests share: Debian's Chromium started headless by puppeteer-core with
// software WebGL (SwiftShader: no GPU needed) and no background connections (the machine may have
// no network), in a profile of its own; and "ok - ..." / "not ok - ..." checks, counted.
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");

// puppeteer-core from MODULES/node_modules, or exits 77 (Skipped) when it or Chromium is missing.
function puppeteerOr77(modules, chromium, script) {
  if (!fs.existsSync(path.join(modules, "puppeteer-core")) || !fs.existsSync(chromium)) {
    console.log(`${script}: skipped: needs puppeteer-core in ${modules} and Chromium at ${chromium}`);
    process.exit(77);
  }
  return require(path.join(modules, "puppeteer-core"));
}

// Runs `use(browser)`, then closes the browser and removes its profile.
async function withChromium(puppeteer, chromium, use) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "lasmesh-chromium-"));
  const browser = await puppeteer.launch({
    executablePath: chromium, headless: true, userDataDir: profile,
    args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-quic",
      "--disable-dev-shm-usage"],
  });
  try {
    return await use(browser);
  } finally {
    await browser.close();
    fs.rmSync(profile, { recursive: true, force: true });
  }
}

function checks() {
  const tally = { failures: 0 };
  tally.check = (what, passed, detail) => {
    console.log(`${passed ? "ok" : "not ok"} - ${what}${passed || detail === undefined ? "" : `: ${detail}`}`);
    if (!passed) tally.failures++;
  };
  return tally;
}

module.exports = { puppeteerOr77, withChromium, checks };
