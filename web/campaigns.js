// Campaigns (/campaigns): every campaign epoch (docs/campaigns.md) with its frame, how many
// segments registered, whether they moved as one, and its C2C; each links to its page.
import { element, formatTime, getJson, header, showError } from './common.js';

const mm = (m) => (m === null || m === undefined ? '—' : `${(m * 1000).toFixed(1)} mm`);

export function movedAsOne(c) {
  if (c.segments_differ === null) return 'not testable';
  const p = c.test_p < 1e-4 ? 'p < 0.0001' : `p = ${c.test_p.toFixed(4)}`;
  return `${c.segments_differ ? 'no' : 'yes'} (${p})`;
}

export function frameText(c) {
  return c.coarse === 'planes' ? `found on ${c.coarse_planes} planes` : 'as given';
}

function table(campaigns) {
  const head = ['Campaign', 'Acquired', 'Instrument', 'Points', 'Frame', 'Segments registered',
    'Moved as one', 'C2C mean', 'C2C 95 %'];
  const t = element('table', { class: 'list campaigns' },
    element('tr', {}, ...head.map((h) => element('th', { text: h }))));
  for (const c of campaigns) {
    t.append(element('tr', { 'data-campaign': String(c.id) },
      element('td', {}, element('a', { href: `/campaigns/${c.id}`, text: `campaign ${c.id}` })),
      element('td', { text: formatTime(c.acquired) }),
      element('td', { text: `${c.instrument} (${c.kind})` }),
      element('td', { class: 'value', text: c.points.toLocaleString('en-GB') }),
      element('td', { text: frameText(c) }),
      element('td', { class: 'value', text: `${c.registered_segments} of ${c.segments}` }),
      element('td', { class: c.segments_differ ? 'significant' : '', text: movedAsOne(c) }),
      element('td', { class: 'value', text: mm(c.c2c_mean_m) }),
      element('td', { class: 'value', text: mm(c.c2c_p95_m) })));
  }
  return t;
}

async function load() {
  try {
    const site = await getJson('/api/v1/site');
    header(site.station, '/campaigns');
    const campaigns = await getJson('/api/v1/campaigns');
    window.tlsmonCampaigns = campaigns;  // what the table shows, for scripts and tests
    document.querySelector('#campaigns').replaceChildren(campaigns.length
      ? table(campaigns.slice().reverse())
      : element('p', { class: 'quiet', text: 'No campaign yet: an [[instrument]]\'s file in the ingest folder, or tlsmon campaign add.' }));
  } catch (e) {
    showError('#campaigns', e);
  }
}

if (document.querySelector('#campaigns')) load();
