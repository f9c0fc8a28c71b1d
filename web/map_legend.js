// The legends under the epoch's and the campaign's maps: a colour bar and an arrow's scale bar.
import { element } from './common.js';

// A colour bar of `colour(t)`, t from 0 to 1, between two labels, with a note after it.
export function colourBar(colour, left, right, note) {
  const bar = element('canvas', { width: 160, height: 12 });
  const ctx = bar.getContext('2d');
  for (let x = 0; x < 160; ++x) {
    ctx.fillStyle = colour(x / 159);
    ctx.fillRect(x, 0, 1, 12);
  }
  return element('div', { class: 'map-legend' }, element('span', { text: left }), bar,
    element('span', { text: right }), element('span', { class: 'quiet', text: note }));
}

// The round length (1, 2 or 5 × 10^k) nearest to `target`.
export function roundLength(target) {
  const base = 10 ** Math.floor(Math.log10(target));
  return [1, 2, 5, 10].map((m) => m * base).reduce((a, b) => (Math.abs(b - target) < Math.abs(a - target) ? b : a));
}

// A scale bar `pixels` long: "label: |——| value (note)".
export function scaleBar(pixels, label, value, note) {
  const bar = element('canvas', { width: Math.ceil(pixels) + 4, height: 12 });
  const ctx = bar.getContext('2d');
  ctx.strokeStyle = '#000';
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(1, 6); ctx.lineTo(1 + pixels, 6);
  ctx.moveTo(1, 1); ctx.lineTo(1, 11);
  ctx.moveTo(1 + pixels, 1); ctx.lineTo(1 + pixels, 11);
  ctx.stroke();
  return element('div', { class: 'map-legend' }, element('span', { text: `${label}: ` }), bar,
    element('span', { text: ` ${value}` }), element('span', { class: 'quiet', text: ` (${note})` }));
}
