// Colour maps for the layers: a perceptual ramp for values, fixed colours for the classes.

/** Viridis, sampled at 9 stops (value in [0, 1] -> [r, g, b] in 0..255). */
const VIRIDIS = [
  [68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141],
  [39, 173, 129], [92, 200, 99], [170, 220, 50], [253, 231, 37]];
/** Green (cheap) to yellow to orange (expensive) for cost, so red stays for lethal. */
const COST = [[26, 152, 80], [145, 207, 96], [217, 239, 139], [254, 224, 139], [252, 141, 89], [215, 100, 40]];

export const UNKNOWN_RGB = [128, 128, 128];
export const LETHAL_RGB = [220, 20, 30];
export const STEINER_TINT = 0.55;

export const RAMPS = { viridis: VIRIDIS, cost: COST };

/** Colour of t in [0, 1] on `ramp` (clamped). */
export function rampColour(ramp, t) {
  const u = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (ramp.length - 1);
  const i = Math.min(ramp.length - 2, Math.floor(u));
  const f = u - i;
  const a = ramp[i], b = ramp[i + 1];
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}

/** CSS linear-gradient of a ramp, for the legend. */
export function rampGradient(ramp) {
  const stops = ramp.map((c, i) => `rgb(${c.join(',')}) ${((100 * i) / (ramp.length - 1)).toFixed(1)}%`);
  return `linear-gradient(to right, ${stops.join(', ')})`;
}
