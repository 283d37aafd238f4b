// The per-keyframe time of each step (keyframes.csv; the paper's Figures 5-6) with a marker at
// the slider's keyframe; clicking the chart moves the slider.
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';

const STEPS = [
  ['time_steiner_s', 'Steiner', '#8dd3c7'],
  ['time_shrink_s', 'shrink', '#fdb462'],
  ['time_insertion_s', 'insertion', '#bebada'],
  ['time_ray_tracing_s', 'ray tracing', '#fb8072'],
  ['time_grow_s', 'grow', '#80b1d3'],
  ['time_total_s', 'total', '#f0f0f0'],
];

/** Per keyframe event (numbered from 1 as snapshots are): the step times in ms. */
export function keyframeTimings(csv) {
  const c = csv.columns;
  const x = [];
  const series = STEPS.map(() => []);
  let keyframe = 0;
  for (let r = 0; r < csv.rows; ++r) {
    if (c.kind && c.kind[r] !== 'keyframe') continue;
    x.push(++keyframe);
    STEPS.forEach(([column], s) => series[s].push(c[column] ? 1000 * c[column][r] : null));
  }
  return { x, series, steps: STEPS.filter(([column]) => c[column]) };
}

export class TimingChart {
  constructor(element, timings, onPick) {
    this.marker = 0;
    const plugin = {
      hooks: {
        draw: [(u) => {
          if (!this.marker) return;
          const left = u.valToPos(this.marker, 'x', true);
          const ctx = u.ctx;
          ctx.save();
          ctx.strokeStyle = '#ffd400';
          ctx.lineWidth = 2;
          ctx.beginPath();
          ctx.moveTo(left, u.bbox.top);
          ctx.lineTo(left, u.bbox.top + u.bbox.height);
          ctx.stroke();
          ctx.restore();
        }],
      },
    };
    const axis = { stroke: '#b8c0ca', grid: { stroke: '#2c3138' }, ticks: { stroke: '#2c3138' } };
    this.plot = new uPlot({
      width: Math.max(300, element.clientWidth - 12),
      height: 170,
      plugins: [plugin],
      scales: { x: { time: false } },
      axes: [{ ...axis, label: 'keyframe' }, { ...axis, label: 'ms', size: 60 }],
      series: [{ label: 'keyframe' }, ...STEPS.map(([, label, colour]) => ({
        label, stroke: colour, width: label === 'total' ? 2 : 1.25, points: { show: false } }))],
      cursor: { drag: { x: false, y: false } },
    }, [timings.x, ...timings.series], element);
    this.plot.over.addEventListener('click', () => {
      const index = this.plot.cursor.idx;
      if (index != null) onPick(timings.x[index]);
    });
    new ResizeObserver(() => this.plot.setSize({ width: Math.max(300, element.clientWidth - 12), height: 170 }))
      .observe(element);
  }

  setMarker(keyframe) {
    this.marker = keyframe;
    this.plot.redraw(false, false);
  }
}
