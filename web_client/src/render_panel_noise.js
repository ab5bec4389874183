// When a progressive server render has converged (docs/PAGE.md "Server render"): each pass has
// RATIO times the samples of the one before, so its noise is 1/√RATIO of that one's; the
// difference of the two images then estimates the newer pass's noise, conservatively, as
// rms(newer − older) / √(RATIO − 1) in 8-bit sRGB levels over every channel of every pixel. The
// render has converged when that estimate is below CONVERGED_LEVELS: more samples would change
// the image by less than its 8-bit steps.

export const RATIO = 4;
export const CONVERGED_LEVELS = 1;

// The RGBA bytes of an image blob.
export async function pixelsOf(blob) {
  const bitmap = await createImageBitmap(blob);
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const context = canvas.getContext('2d');
  context.drawImage(bitmap, 0, 0);
  bitmap.close();
  return context.getImageData(0, 0, canvas.width, canvas.height).data;
}

// The newer pass's estimated noise (8-bit levels, RMS) from two passes of the same view whose
// samples differ by `ratio`; null when they cannot be compared.
export function noiseLevels(older, newer, ratio = RATIO) {
  if (!older || !newer || older.length !== newer.length || ratio <= 1) return null;
  let sum = 0, n = 0;
  for (let i = 0; i < newer.length; i += 4) {
    for (let c = 0; c < 3; ++c) {
      const d = newer[i + c] - older[i + c];
      sum += d * d;
    }
    n += 3;
  }
  return n ? Math.sqrt(sum / n) / Math.sqrt(ratio - 1) : null;
}
