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

// How long a page may take to load or answer: generous, since software WebGL on a loaded 2-core
// machine (sanitized builds beside it) is many times slower than here; a page that fails says
// so at once, through its own error state.
const patience = 480000;

// Runs `use(browser)`, then closes the browser and removes its profile.
async function withChromium(puppeteer, chromium, use) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "lasmesh-chromium-"));
  const browser = await puppeteer.launch({
    executablePath: chromium, headless: true, userDataDir: profile, timeout: patience, protocolTimeout: patience,
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

// A new tab whose waits (navigation, waitForFunction) last `patience`.
async function newTab(browser) {
  const page = await browser.newPage();
  page.setDefaultTimeout(patience);
  page.setDefaultNavigationTimeout(patience);
  return page;
}

module.exports = { puppeteerOr77, withChromium, checks, newTab, patience };
