// Colour maps for the layers: a perceptual ramp for values, fixed colours for the classes.

/** Viridis, sampled at 9 stops (value in [0, 1] -> [r, g, b] in 0..255). */
const VIRIDIS = [
  [68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141],
  [39, 173, 129], [92, 200, 99], [170, 220, 50], [253, 231, 37]];
/** Green (cheap) to yellow to orange (expensive) for cost, so red stays for lethal. */
const COST = [[26, 152, 80], [145, 207, 96], [217, 239, 139], [254, 224, 139], [252, 141, 89], [215, 100, 40]];

/**
 * Unknown faces are achromatic (no ramp has a grey) and hatched: the scene's shader draws
 * diagonal stripes of UNKNOWN_HATCH_RGB over them, 3 px of every HATCH_PERIOD_PX, in screen space.
 */
export const UNKNOWN_RGB = [128, 128, 128];
export const UNKNOWN_HATCH_RGB = [225, 225, 225];
export const HATCH_PERIOD_PX = 6;
export const LETHAL_RGB = [220, 20, 30];
/** Uncertain faces (measured, the evidence cannot decide): magenta, a hue no ramp and not lethal red has. */
export const UNCERTAIN_RGB = [235, 60, 190];
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

/** The CSS of the unknown swatch: the same stripes as the map (scene.js). */
export function hatchCss() {
  const base = `rgb(${UNKNOWN_RGB.join(',')})`, stripe = `rgb(${UNKNOWN_HATCH_RGB.join(',')})`;
  const half = HATCH_PERIOD_PX / 2;
  return `repeating-linear-gradient(-45deg, ${stripe} 0 ${half}px, ${base} ${half}px ${HATCH_PERIOD_PX}px)`;
}

/** CSS linear-gradient of a ramp, for the legend. */
export function rampGradient(ramp) {
  const stops = ramp.map((c, i) => `rgb(${c.join(',')}) ${((100 * i) / (ramp.length - 1)).toFixed(1)}%`);
  return `linear-gradient(to right, ${stops.join(', ')})`;
}
