// The legend: the layer's colour ramp with its range and units, and the class swatches.
import { LETHAL_RGB, UNCERTAIN_RGB, hatchCss, rampGradient } from './colormaps.js';

function format(value) {
  if (!Number.isFinite(value)) return String(value);
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude >= 1e4 || magnitude < 1e-2)) return value.toExponential(1);
  return value.toFixed(magnitude >= 100 ? 0 : 2);
}

/**
 * Renders {title, ramp, min, max, classes: bool, unknownFaces, lethalFaces, uncertainFaces, note} into `element`;
 * the class swatches are drawn as the map draws those faces (unknown: grey with stripes).
 */
export function renderLegend(element, { title, ramp, min, max, classes, unknownFaces, lethalFaces, uncertainFaces, note }) {
  const swatch = (css, cls) => `<span class="swatch ${cls}" style="background: ${css}"></span>`;
  const count = (n) => (Number.isFinite(n) ? ` (${n})` : '');
  element.innerHTML = `
    <div class="title">${title}</div>
    <div class="bar" style="background: ${rampGradient(ramp)}"></div>
    <div class="ticks"><span>${format(min)}</span><span>${format((min + max) / 2)}</span><span>${format(max)}</span></div>
    ${classes ? `<div class="classes">${swatch(hatchCss(), 'unknown')}unknown, hatched grey${count(unknownFaces)}` +
      `${swatch(`rgb(${LETHAL_RGB.join(',')})`, 'lethal')}lethal${count(lethalFaces)}` +
      `${swatch(`rgb(${UNCERTAIN_RGB.join(',')})`, 'uncertain')}uncertain${count(uncertainFaces)}</div>` : ''}
    ${note ? `<div class="note">${note}</div>` : ''}`;
}
