// Alarms (/alarms): every rule's ISA-18.2 state and the alarm history, newest first.
import {
  element, formatTime, formatValue, getJson, header, onEpochCommitted, showError, stateClass, unit, zoneLink,
} from './common.js';

async function refresh() {
  try {
    const [site, alarms] = await Promise.all([getJson('/api/v1/site'), getJson('/api/v1/alarms')]);
    header(site.station, '/alarms');
    const quantityOf = Object.fromEntries(alarms.states.map((a) => [a.rule, a.quantity]));
    const states = element('table', { class: 'list' }, element('tr', {},
      ...['Rule', 'Zone', 'Quantity', 'State', 'Level', 'Since', 'Value', 'Shelved until'].map((h) => element('th', { text: h }))));
    for (const a of alarms.states) {
      states.append(element('tr', { 'data-rule': a.rule },
        element('td', { text: a.rule }),
        element('td', {}, zoneLink(a.zone)),
        element('td', { text: a.quantity }),
        element('td', {}, element('span', { class: stateClass(a.state), text: a.state })),
        element('td', { text: a.level }),
        element('td', { text: formatTime(a.since) }),
        element('td', { text: a.value === null ? '—' : `${formatValue(a.quantity, a.value)} ${unit(a.quantity)}` }),
        element('td', { text: formatTime(a.shelved_until) })));
    }
    const history = element('table', { class: 'list' }, element('tr', {},
      ...['Time', 'Rule', 'Event', 'Level', 'Value', 'By', 'Message'].map((h) => element('th', { text: h }))));
    for (const e of alarms.events.slice().reverse()) {
      const q = quantityOf[e.rule] ?? '';
      history.append(element('tr', {},
        element('td', { text: formatTime(e.time) }),
        element('td', { text: e.rule }),
        element('td', { text: e.kind }),
        element('td', { text: e.level }),
        element('td', { text: e.value === null ? '—' : `${formatValue(q, e.value)} ${unit(q)}` }),
        element('td', { text: e.actor }),
        element('td', { text: e.message })));
    }
    document.querySelector('#states').replaceChildren(states);
    document.querySelector('#history').replaceChildren(history);
  } catch (e) {
    showError('#states', e);
  }
}

refresh();
onEpochCommitted(refresh);
