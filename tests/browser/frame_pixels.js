// SPDX-License-Identifier: Apache-2.0
// The fraction of a WebGL canvas's pixels that are not the background colour: what a viewer drew.
// The canvas needs preserveDrawingBuffer so that its last frame can still be read.
function coveredFraction(canvas, background) {
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
  for (let i = 0; i < pixels.length; i += 4) {
    const difference = Math.abs(pixels[i] - br) + Math.abs(pixels[i + 1] - bg) + Math.abs(pixels[i + 2] - bb);
    if (difference > 40) covered++;
  }
  return covered / (pixels.length / 4);
}
