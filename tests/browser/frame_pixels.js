// SPDX-License-Identifier: Apache-2.0
// What a viewer drew on a WebGL canvas: the share of its pixels that differ from the background
// colour by more than `tolerance` (the sum over red, green, blue), and their mean colour. The
// canvas needs preserveDrawingBuffer so that its last frame can still be read. Loaded by the test
// pages, and put into lasmesh's own pages by html_page.js.
function framePixels(canvas, background, tolerance) {
  const probe = document.createElement("canvas");
  probe.width = 1; probe.height = 1;
  const probeContext = probe.getContext("2d");
  probeContext.fillStyle = background;
  probeContext.fillRect(0, 0, 1, 1);
  const [br, bg, bb] = probeContext.getImageData(0, 0, 1, 1).data;
  const copy = document.createElement("canvas");
  copy.width = canvas.width; copy.height = canvas.height;
  const context = copy.getContext("2d");
  context.drawImage(canvas, 0, 0);
  const pixels = context.getImageData(0, 0, copy.width, copy.height).data;
  let covered = 0;
  const sum = [0, 0, 0];
  for (let i = 0; i < pixels.length; i += 4) {
    const difference = Math.abs(pixels[i] - br) + Math.abs(pixels[i + 1] - bg) + Math.abs(pixels[i + 2] - bb);
    if (difference <= tolerance) continue;
    covered++;
    for (let k = 0; k < 3; k++) sum[k] += pixels[i + k];
  }
  return { covered: covered / (pixels.length / 4), mean: sum.map((s) => s / Math.max(covered, 1)) };
}
