"use strict";
// hivex replay: plays recorded episodes back. The data is the trace of docs/replay.md (gzip + base64 in
// #replay-data), the frames data URIs in #replay-frames. One decision is shown at a time: the slider, the play
// button and the arrow keys move it, and with it the frames, every chart's cursor, the table and the agent's detail.

const PALETTE = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#ff9da7",
  "#9c755f", "#bab0ac", "#17becf", "#8c564b", "#bcbd22", "#7f7f7f"];
const EVENT_COLOURS = {event: "#6a3d9a", terminated: "#b3261e", truncated: "#5f6b76", "world ended": "#000000",
  schedule: "#0b6bcb"};
const SPEEDS = [1, 5, 10, 25, 50, 100, 250];  // decisions per second
const view = {decision: 1, agent: 0, playing: false, charts: [], agentCharts: []};
let trace, about, frames, episodes, last, termColour;

async function unpack(id) {
  const bytes = Uint8Array.from(atob(document.getElementById(id).textContent.trim()), c => c.charCodeAt(0));
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
  return JSON.parse(await new Response(stream).text());
}

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (key.startsWith("data-") || key === "class") node.setAttribute(key, value);
    else node[key] = value;
  }
  node.append(...children);
  return node;
}

const $ = id => document.getElementById(id);
const swatch = colour => { const chip = el("span", {class: "swatch"}); chip.style.background = colour; return chip; };
const fmt = v => v == null ? "–" : (v !== 0 && (Math.abs(v) >= 1e5 || Math.abs(v) < 1e-3)) ? v.toExponential(3)
  : String(+v.toFixed(4));
const row = (rows, d) => (d >= 1 && d <= rows.length) ? rows[d - 1] : null;  // decision d's row; null after the end
const label = i => episodes.length > 1 ? `${"AB"[i]}: ` : "";
const policyName = p => p.kind === "checkpoint" ? `checkpoint ${p.checkpoint}` : `${p.kind} policy`;

function describeEpisode(e) {
  const s = e.scenario;
  const where = s.level == null ? "" : `, ${s.level_name} ${s.level}`;
  const point = Object.keys(s.sweep_point).length ? `, point ${JSON.stringify(s.sweep_point)}` : "";
  return `${s.name} (${s.environment}, task ${s.task}${where}${point}), ${policyName(e.policy)}, ${e.split} seed` +
    `${e.seed == null ? "s" : " " + e.seed}: ${e.decisions} decisions of ${e.agents.length} agents`;
}

// ---- charts (uPlot) -------------------------------------------------------------------------------------

function eventMarks(episode) {  // ticks at the top of the plot for the world's events and the picked agent's
  return {hooks: {draw: u => {
    const {ctx} = u, {top} = u.bbox, size = 8 * devicePixelRatio;
    for (const ev of episode.events) {
      if (ev.agent !== null && ev.agent !== view.agent) continue;
      ctx.fillStyle = EVENT_COLOURS[ev.kind] || "#000";
      ctx.fillRect(Math.round(u.valToPos(ev.decision, "x", true)) - devicePixelRatio, top, 2 * devicePixelRatio, size);
    }
  }}};
}

function chart(parent, title, note, series, columns, episode) {
  const box = el("div", {class: "chart"}, el("h3", {}, title), el("p", {class: "note"}, note));
  parent.append(box);
  const opts = {
    width: Math.max(280, box.clientWidth - 16), height: 190,
    scales: {x: {time: false, range: () => [1, Math.max(last, 2)]}},  // one decision still gets an axis
    axes: [{label: "decision", size: 36, labelSize: 14}, {size: 60}],
    cursor: {sync: {key: "replay"}, drag: {x: false, y: false}},
    series: [{label: "decision"}, ...series],
    plugins: episode ? [eventMarks(episode)] : [],
  };
  const u = new uPlot(opts, columns, box);
  u.box = box;
  u.over.addEventListener("click", () => u.cursor.idx != null && setDecision(u.data[0][u.cursor.idx]));
  view.charts.push(u);
  return u;
}

const decisionsOf = e => Array.from({length: e.decisions}, (_, t) => t + 1);

function stackedSeries(e, agent) {
  // gains stacked up from 0, costs down; each layer is the running sum of the terms below it, drawn outermost
  // first so that the inner layers paint over it (the legend shows each term's own weighted value)
  const layers = [];
  for (const sign of [1, -1]) {
    const stack = [];
    let sum = new Array(e.decisions).fill(0);
    for (const term of e.terms) {
      const own = e.weighted[term].map(r => sign > 0 ? Math.max(r[agent], 0) : Math.min(r[agent], 0));
      if (!own.some(v => v !== 0)) continue;
      sum = sum.map((s, t) => s + own[t]);
      stack.push({term, own: e.weighted[term].map(r => r[agent]), values: sum, sign});
    }
    layers.push(...stack.reverse());
  }
  const series = layers.map(l => ({label: e.term_titles[l.term] + (l.sign < 0 ? " (cost)" : ""),
    stroke: termColour[l.term], fill: termColour[l.term], width: 0, fillTo: () => 0, points: {show: false},
    value: (u, v, s, i) => i == null ? "–" : fmt(l.own[i])}));
  series.push({label: "reward", stroke: "#111", width: 1.5, points: {show: false}});
  return {series, columns: [...layers.map(l => l.values), e.reward.map(r => r[agent])]};
}

function runningSeries(e, agent) {
  const cumulative = values => { let s = 0; return values.map(v => (s += v)); };
  const series = e.terms.map(term => ({label: e.term_titles[term], stroke: termColour[term], width: 1.5,
    points: {show: false}}));
  series.push({label: "return", stroke: "#111", width: 2.5, points: {show: false}});
  const columns = e.terms.map(term => cumulative(e.weighted[term].map(r => r[agent])));
  columns.push(cumulative(e.reward.map(r => r[agent])));
  return {series, columns};
}

function buildAgentCharts() {
  for (const u of view.agentCharts) { u.destroy(); view.charts.splice(view.charts.indexOf(u), 1); }
  const parent = $("charts-agent");
  parent.replaceChildren();
  $("agent-title").textContent = `${episodes[0].agents[view.agent]}: reward by term`;
  // one row per kind of chart, the compared episodes side by side
  const stacked = episodes.map((e, i) => () => {
    const {series, columns} = stackedSeries(e, view.agent);
    return chart(parent, `${label(i)}${e.agents[view.agent]}: weighted reward per decision`, "each term's weighted " +
      "value, gains up and costs down; the black line is the reward the environment returned", series,
      [decisionsOf(e), ...columns], e);
  });
  const running = episodes.map((e, i) => () => {
    const {series, columns} = runningSeries(e, view.agent);
    return chart(parent, `${label(i)}${e.agents[view.agent]}: running total by term`, "each term's weighted sum " +
      "so far; the black line is the return", series, [decisionsOf(e), ...columns], e);
  });
  view.agentCharts = (episodes.length > 1 ? [...stacked, ...running] : [stacked[0], running[0]]).map(make => make());
}

function buildWorldCharts() {
  const parent = $("charts-world");
  const names = episodes[0].statistics;
  const published = new Set(episodes[0].published_statistics);
  const ordered = [...names.filter(n => published.has(n)), ...names.filter(n => !published.has(n))];
  for (const name of ordered) {
    const series = episodes.map((e, i) => ({label: episodes.length > 1 ? "AB"[i] : "mean", stroke: PALETTE[i * 3],
      width: 1.5, points: {show: false}}));
    const columns = episodes.map(e => {
      const values = (e.statistics_so_far[name] || []).map(r => r.reduce((a, b) => a + b, 0) / r.length);
      return Array.from({length: last}, (_, t) => t < values.length ? values[t] : null);
    });
    const x = Array.from({length: last}, (_, t) => t + 1);
    chart(parent, name + (published.has(name) ? " (published)" : ""),
      episodes[0].statistic_descriptions[name] || "", series, [x, ...columns], episodes[0]);
  }
}

// ---- the panels that follow the decision ------------------------------------------------------------------

function frameIndex(e, d) {  // the last frame taken at or before decision d
  let j = 0;
  while (j + 1 < e.frame_decisions.length && e.frame_decisions[j + 1] <= d) j++;
  return j;
}

function buildFrames() {
  $("world").replaceChildren(...episodes.map((e, i) => el("figure", {},
    el("img", {id: `frame-${i}`, alt: `world of episode ${i + 1}`}), el("figcaption", {id: `caption-${i}`}))));
}

function showFrames(d) {
  episodes.forEach((e, i) => {
    const j = frameIndex(e, d);
    $(`frame-${i}`).src = frames[i][j];
    $(`caption-${i}`).textContent = `${label(i)}the world after decision ${e.frame_decisions[j]} (a frame every ` +
      `${e.frame_step} decisions and after the last)`;
  });
}

function cell(value, attrs = {}, className = "") {
  const shown = typeof value === "number" ? fmt(value) : (value ?? "–");
  const c = el("td", {...attrs, class: className}, shown);
  if (typeof value === "number") c.setAttribute("data-value", String(value));
  return c;
}

function showTerms(d) {
  const a = view.agent, head = el("tr", {}, el("th", {}, "term"));
  episodes.forEach((e, i) => head.append(el("th", {}, `${label(i)}unweighted`), el("th", {}, `${label(i)}weight`),
    el("th", {}, `${label(i)}weighted`)));
  const rows = [el("thead", {}, head)], body = el("tbody");
  const terms = [...new Set(episodes.flatMap(e => e.terms))];
  for (const term of terms) {
    const tr = el("tr", {}, el("td", {}, swatch(termColour[term]),
      episodes.find(e => term in e.term_titles).term_titles[term]));
    episodes.forEach((e, i) => {
      const known = term in e.weighted, w = known ? row(e.weighted[term], d) : null;
      const at = {"data-episode": i, "data-term": term};
      tr.append(cell(known ? row(e.raw[term], d)?.[a] : null, {...at, "data-column": "value"}),
        cell(known ? row(e.weights[term], d) : null, {...at, "data-column": "weight"}),
        cell(w ? w[a] : null, {...at, "data-column": "weighted"}, w ? (w[a] > 0 ? "gain" : w[a] < 0 ? "cost" : "") : ""));
    });
    body.append(tr);
  }
  const total = el("tr", {class: "total"}, el("td", {}, "sum of the weighted terms"));
  const env = el("tr", {class: "env"}, el("td", {}, "reward the environment returned"));
  episodes.forEach((e, i) => {
    const sum = row(e.reward, d) ? e.terms.reduce((s, t) => s + row(e.weighted[t], d)[a], 0) : null;
    total.append(el("td"), el("td"), cell(sum == null ? null : +sum.toPrecision(trace.digits),
      {"data-episode": i, "data-column": "sum"}));
    const playing = row(e.playing, d)?.[a];
    env.append(el("td", {}, playing === false ? "(episode over)" : ""), el("td"),
      cell(row(e.reward, d)?.[a], {"data-episode": i, "data-column": "reward"}));
  });
  body.append(total, env);
  $("terms").replaceChildren(...rows, body);
}

function showAgent(d) {
  const a = view.agent, e0 = episodes[0];
  const header = () => el("thead", {}, el("tr", {}, el("th"), ...episodes.map((_, i) => el("th", {}, "AB"[i]))));
  const table = (title, note, names, valuesOf) => el("div", {}, el("h3", {}, title), el("p", {class: "note"}, note),
    el("table", {}, ...(episodes.length > 1 ? [header()] : []), el("tbody", {}, ...names.map((name, k) =>
      el("tr", {}, el("td", {}, name), ...episodes.map((e, i) => cell(row(valuesOf(e), d)?.[a]?.[k], {"data-episode": i})))))));
  const actionNames = (row(e0.actions, 1)?.[a] || []).map((_, k) => `[${k}]`);
  const over = episodes.map((e, i) => row(e.playing, d)?.[a] === false ? `${label(i)}its episode is over: the ` +
    "environment ignores this action and pays nothing" : "").filter(Boolean).join("; ");
  $("agent-detail").replaceChildren(
    table(`${e0.agents[a]}: action`, over || e0.action_meanings, actionNames, e => e.actions),
    table("observation before it", "the vector observation (no camera)", e0.observation_labels, e => e.observations));
}

function showEvents(d) {
  for (const li of $("events").children) li.classList.toggle("past", +li.dataset.decision > d);
}

function eventRuns(e, i) {  // the episode's events of the world and the picked agent, a run on consecutive decisions as one
  const runs = [];
  for (const ev of e.events.filter(ev => ev.agent === null || ev.agent === view.agent)) {
    const open = runs.find(r => r.until === ev.decision - 1 && r.agent === ev.agent && r.name === ev.name);
    if (open) open.until = ev.decision;
    else runs.push({...ev, until: ev.decision, i});
  }
  return runs;
}

function buildEvents() {
  const items = episodes.flatMap(eventRuns).sort((p, q) => p.decision - q.decision);
  $("events").replaceChildren(...items.map(ev => {
    const who = ev.agent === null ? "world" : episodes[ev.i].agents[ev.agent];
    const when = ev.until > ev.decision ? `decisions ${ev.decision}-${ev.until}` : `decision ${ev.decision}`;
    const li = el("li", {"data-decision": ev.decision}, swatch(EVENT_COLOURS[ev.kind] || "#000"),
      `${label(ev.i)}${when}: ${who} ${ev.name}`);
    li.addEventListener("click", () => setDecision(ev.decision));
    return li;
  }));
  if (!items.length) $("events").append(el("li", {}, "none for this agent or the world"));
}

function buildAbout() {
  const parts = [el("h2", {}, "Scenario and policy")];
  about.forEach((ab, i) => {
    const e = episodes[i], lock = ab.lock;
    const policy = Object.entries(e.policy).map(([k, v]) => `${k}: ${v}`).join("\n");
    parts.push(el("h3", {}, `${label(i)}${describeEpisode(e)}`),
      el("details", {}, el("summary", {}, `Scenario as written (${ab.source})`),
        el("pre", {}, ab.written ?? "(not from a file: the checkpoint holds the scenario as resolved, below)")),
      el("details", {}, el("summary", {}, `Scenario as resolved: its lock, fingerprint ${lock.fingerprint}`),
        el("pre", {}, JSON.stringify(lock, null, 2))),
      el("details", {open: true}, el("summary", {}, `Policy: ${policyName(e.policy)}`), el("pre", {}, policy)));
  });
  $("about").replaceChildren(...parts);
}

// ---- the decision and playback ----------------------------------------------------------------------------

function setDecision(d) {
  view.decision = Math.min(Math.max(1, Math.round(d)), last);
  const d0 = view.decision;
  $("slider").value = d0;
  $("position").textContent = `decision ${d0} of ${last}`;
  showFrames(d0);
  showTerms(d0);
  showAgent(d0);
  showEvents(d0);
  for (const u of view.charts) {
    const idx = Math.min(d0, u.data[0].length) - 1;
    u.setCursor({left: u.valToPos(u.data[0][idx], "x"), top: u.bbox.height / devicePixelRatio / 2}, false);
  }
}

function fitCharts() {  // every chart as wide as its box, once the grid has laid the boxes out
  for (const u of view.charts) u.setSize({width: Math.max(280, u.box.clientWidth - 16), height: 190});
}

function setAgent(a) {
  view.agent = a;
  buildAgentCharts();
  buildEvents();
  fitCharts();
  for (const u of view.charts) u.redraw(false);
  setDecision(view.decision);
}

function togglePlay() {
  view.playing = !view.playing;
  $("play").innerHTML = view.playing ? "&#10074;&#10074; pause" : "&#9654; play";
  if (!view.playing) return;
  if (view.decision >= last) setDecision(1);
  let before = performance.now(), carry = 0;
  const tick = now => {
    if (!view.playing) return;
    carry += (now - before) / 1000 * +$("speed").value;
    before = now;
    if (carry >= 1) { setDecision(view.decision + Math.floor(carry)); carry %= 1; }
    if (view.decision >= last) return togglePlay();
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

function onKey(event) {
  if (event.target.tagName === "SELECT") return;
  const jump = event.shiftKey ? 10 : 1;
  const moves = {ArrowRight: view.decision + jump, ArrowLeft: view.decision - jump, Home: 1, End: last};
  if (event.key in moves) { event.preventDefault(); setDecision(moves[event.key]); }
  else if (event.key === " ") { event.preventDefault(); togglePlay(); }
}

function buildControls() {
  const speed = $("speed"), agent = $("agent");
  speed.append(...SPEEDS.map(s => el("option", {value: s}, `${s} / s`)));
  speed.value = SPEEDS.find(s => s >= last / 60) || SPEEDS[SPEEDS.length - 1];  // about a minute for an episode
  agent.append(...episodes[0].agents.map((name, a) => el("option", {value: a}, name)));
  Object.assign($("slider"), {min: 1, max: last});
  $("slider").addEventListener("input", event => setDecision(+event.target.value));
  agent.addEventListener("change", event => setAgent(+event.target.value));
  $("play").addEventListener("click", togglePlay);
  document.addEventListener("keydown", onKey);
}

async function main() {
  ({trace, about} = await unpack("replay-data"));
  frames = JSON.parse($("replay-frames").textContent);
  episodes = trace.episodes;
  last = Math.max(...episodes.map(e => e.decisions));
  const terms = [...new Set(episodes.flatMap(e => e.terms))];
  termColour = Object.fromEntries(terms.map((t, k) => [t, PALETTE[k % PALETTE.length]]));
  $("summary").textContent = episodes.map((e, i) => label(i) + describeEpisode(e)).join(" | ");
  buildControls();
  buildFrames();
  buildAgentCharts();
  buildWorldCharts();
  buildEvents();
  buildAbout();
  fitCharts();
  window.addEventListener("resize", () => { fitCharts(); setDecision(view.decision); });
  setDecision(1);
  window.replay = {view, trace, setDecision, setAgent};
  document.body.dataset.ready = "true";
}

main().catch(error => {
  document.body.prepend(el("p", {class: "cost"}, `This replay could not be opened: ${error}`));
  throw error;
});
