// The legend: the layer's colour ramp with its range and units, and the class swatches.
import { LETHAL_RGB, UNKNOWN_RGB, rampGradient } from './colormaps.js';

function format(value) {
  if (!Number.isFinite(value)) return String(value);
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude >= 1e4 || magnitude < 1e-2)) return value.toExponential(1);
  return value.toFixed(magnitude >= 100 ? 0 : 2);
}

/** Renders {title, ramp, min, max, classes: bool, note} into `element`. */
export function renderLegend(element, { title, ramp, min, max, classes, note }) {
  const swatch = (rgb) => `<span class="swatch" style="background: rgb(${rgb.join(',')})"></span>`;
  element.innerHTML = `
    <div class="title">${title}</div>
    <div class="bar" style="background: ${rampGradient(ramp)}"></div>
    <div class="ticks"><span>${format(min)}</span><span>${format((min + max) / 2)}</span><span>${format(max)}</span></div>
    ${classes ? `<div>${swatch(UNKNOWN_RGB)}unknown ${swatch(LETHAL_RGB)}lethal</div>` : ''}
    ${note ? `<div class="note">${note}</div>` : ''}`;
}
