// The system manager's page: the installed diagram, coloured by what the manager sends.
// Plain JavaScript, no library: every file comes from the manager (robmosys_runtime.web).
'use strict';

const token = new URLSearchParams(location.search).get('token') || '';
const entries = {};
let selected = null;

function stateClass(state) {
  if (state === 'active' || state === 'running') return 'state-active';
  if (state === 'failed' || state === 'exited') return 'state-failed';
  if (state === 'unknown' || state === 'elsewhere') return 'state-unknown';
  return 'state-inactive';
}

function element(tag, text, className) {
  const made = document.createElement(tag);
  if (text !== undefined) made.textContent = text;
  if (className) made.className = className;
  return made;
}

function shown(value) {
  return value === null || value === undefined ? 'not read' : JSON.stringify(value);
}

function paint(key) {
  const entry = entries[key];
  if (key === 'system') {
    document.getElementById('title').textContent = entry.package;
    document.title = entry.package;
    document.getElementById('watch').textContent = 'watch: ' + entry.watch +
      (entry.up ? '' : ' (brought down)');
    const mode = document.getElementById('mode');
    mode.hidden = entry.mode === null && !entry.modes.length;
    mode.replaceChildren(element('span', 'mode: ' + (entry.mode === null ? 'none' : entry.mode)));
    for (const name of entry.modes) {
      const button = element('button', name);
      button.type = 'button';
      button.dataset.mode = name;
      button.disabled = name === entry.mode;
      button.addEventListener('click', () => act('mode', {mode: name}));
      mode.appendChild(button);
    }
    return;
  }
  const [kind, name] = [key.slice(0, 1), key.slice(2)];
  const group = kind === 'i' ?
    document.querySelector(`g.instance[data-instance="${CSS.escape(name)}"]`) :
    document.querySelector(`g.connection[data-connection="${CSS.escape(name)}"]`);
  if (!group || !entry) return;
  if (kind === 'i') {
    group.classList.remove('state-active', 'state-failed', 'state-unknown', 'state-inactive');
    group.classList.add(stateClass(entry.state));
    group.classList.toggle('differs', entry.differences.length > 0);
    group.dataset.state = entry.state;
  } else {
    group.classList.remove('conn-conforms', 'conn-differs', 'conn-unknown');
    group.classList.add('conn-' + entry.status);
    group.dataset.status = entry.status;
  }
  if (selected === key) details(key);
}

function differences(box, lines) {
  box.appendChild(element('h3', lines.length ? 'Differences' : 'No difference'));
  const list = element('ul');
  for (const line of lines) list.appendChild(element('li', line, 'differs'));
  box.appendChild(list);
}

function details(key) {
  const entry = entries[key];
  const box = document.getElementById('what');
  box.replaceChildren();
  document.getElementById('details').hidden = false;
  if (!entry) return;
  if (key.startsWith('i:')) {
    box.appendChild(element('h2', key.slice(2)));
    const table = element('table');
    for (const [label, value] of [['node', entry.fqn], ['state', entry.state + (entry.why ? ' (' + entry.why + ')' : '')],
      ['host', entry.host || "the manager's"], ['model', entry.location]]) {
      const row = element('tr');
      row.append(element('th', label), element('td', value));
      table.appendChild(row);
    }
    box.appendChild(table);
    if (entry.parameters.length) {
      box.appendChild(element('h3', 'Parameters'));
      const values = element('table', undefined, 'parameters');
      const head = element('tr');
      head.append(element('th', 'name'), element('th', 'model'), element('th', 'running'));
      values.appendChild(head);
      for (const [name, model, running, where] of entry.parameters) {
        const row = element('tr');
        const differs = running !== null && JSON.stringify(running) !== JSON.stringify(model);
        row.append(element('td', name), element('td', shown(model)),
          element('td', shown(running), differs ? 'differs' : ''));
        row.title = where;
        row.dataset.parameter = name;
        values.appendChild(row);
      }
      box.appendChild(values);
    }
    differences(box, entry.differences);
  } else {
    const group = document.querySelector(`g.connection[data-connection="${CSS.escape(key.slice(2))}"]`);
    box.appendChild(element('h2', entry.name));
    const table = element('table');
    for (const [label, value] of [['from', entry.from], ['to', entry.to], ['type', entry.type],
      ['QoS', group ? group.dataset.qos : ''], ['status', entry.status], ['model', entry.location]]) {
      const row = element('tr');
      row.append(element('th', label), element('td', value));
      table.appendChild(row);
    }
    box.appendChild(table);
    differences(box, entry.differences);
  }
}

function select(key) {
  document.querySelectorAll('svg .selected').forEach((e) => e.classList.remove('selected'));
  selected = key;
  const [kind, name] = [key.slice(0, 1), key.slice(2)];
  const group = kind === 'i' ?
    document.querySelector(`g.instance[data-instance="${CSS.escape(name)}"]`) :
    document.querySelector(`g.connection[data-connection="${CSS.escape(name)}"]`);
  if (group) group.classList.add('selected');
  details(key);
}

function apply(message) {
  const data = JSON.parse(message.data);
  for (const [key, entry] of Object.entries(data.entries)) {
    entries[key] = entry;
    paint(key);
  }
  for (const key of data.gone) delete entries[key];
  document.body.dataset.version = data.version;
}

function listen() {
  // EventSource reconnects by itself when the stream ends (the manager restarted);
  // the first event of every stream is every entry
  const events = new EventSource('events');
  const live = document.getElementById('live');
  events.addEventListener('state', (message) => {
    live.textContent = 'live';
    live.className = 'live-on';
    apply(message);
  });
  events.addEventListener('change', apply);
  events.onerror = () => {
    live.textContent = 'reconnecting';
    live.className = 'live-connecting';
  };
}

async function act(name, arguments_ = {}) {
  const answer = document.getElementById('answer');
  answer.textContent = name.replace('_', ' ') + '...';
  try {
    const response = await fetch('action/' + name, {
      method: 'POST', headers: {'X-Robmosys-Token': token, 'Content-Type': 'application/json'},
      body: JSON.stringify(arguments_)});
    const result = await response.json();
    answer.textContent = (response.status === 403 ? 'refused: ' : '') + result.message;
  } catch (error) {
    answer.textContent = 'the manager did not answer: ' + error;
  }
}

async function start() {
  const response = await fetch('diagram.svg');
  document.getElementById('diagram').innerHTML = await response.text();
  document.querySelectorAll('g.instance').forEach((g) =>
    g.addEventListener('click', () => select('i:' + g.dataset.instance)));
  document.querySelectorAll('g.connection').forEach((g) =>
    g.addEventListener('click', () => select('c:' + g.dataset.connection)));
  document.getElementById('close').addEventListener('click', () => {
    document.getElementById('details').hidden = true;
    selected = null;
  });
  for (const name of ['bring_up', 'bring_down']) {
    document.getElementById(name).addEventListener('click', () => act(name));
  }
  listen();
}

start();
