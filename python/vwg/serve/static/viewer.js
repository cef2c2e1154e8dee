// vwg live viewer: draws the frames the server sends over the WebSocket on the map image, and sends
// the user's orders (a room button, a click on a marker) and controls. Plain JavaScript, no libraries.
"use strict";

const canvas = document.getElementById("map");
const ctx = canvas.getContext("2d");
const statusLine = document.getElementById("status");
const errors = document.getElementById("errors");
const robotSelect = document.getElementById("robot");
let world = null;
let mapImage = null;
let frame = null;
let socket = null;
let selecting = null;  // a robot chosen here that the server's frames do not show as selected yet

function px(x, y) {
  const m = world.map;
  return [m.ax * x + m.bx, m.ay * y + m.by];
}

function showError(text) {
  errors.textContent = text;
}

function send(message) {
  if (!socket || socket.readyState !== WebSocket.OPEN) {
    showError("not connected to the server");
    return;
  }
  socket.send(JSON.stringify(message));
}

function colour(id) {
  const robot = world.robots.find((r) => r.id === id);
  return robot ? `rgb(${robot.colour.join(",")})` : "#333";
}

function draw() {
  if (!world || !mapImage) return;
  ctx.drawImage(mapImage, 0, 0);
  if (!frame) return;
  for (const person of frame.people || []) {  // people who walk: sand discs, as in the videos
    const [u, v] = px(person.x, person.y);
    ctx.fillStyle = "rgb(222, 184, 135)";
    ctx.strokeStyle = "rgb(20, 20, 24)";
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.arc(u, v, Math.max(4, Math.abs(world.map.ax) * person.radius), 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
  }
  for (const robot of frame.robots) {
    ctx.fillStyle = "rgba(220, 40, 40, 0.7)";
    for (const [x, y] of robot.scan) {
      const [u, v] = px(x, y);
      ctx.fillRect(u - 1, v - 1, 2, 2);
    }
    if (robot.path.length > 1) {
      ctx.strokeStyle = colour(robot.id);
      ctx.lineWidth = 2;
      ctx.setLineDash([6, 4]);
      ctx.beginPath();
      robot.path.forEach(([x, y], i) => {
        const [u, v] = px(x, y);
        if (i === 0) ctx.moveTo(u, v); else ctx.lineTo(u, v);
      });
      ctx.stroke();
      ctx.setLineDash([]);
    }
    const [u, v] = px(robot.x, robot.y);
    const r = Math.max(4, Math.abs(world.map.ax) * robot.radius);
    ctx.fillStyle = colour(robot.id);
    ctx.beginPath();
    ctx.arc(u, v, r, 0, 2 * Math.PI);
    ctx.fill();
    ctx.strokeStyle = robot.id === frame.selected ? "#000" : "#fff";
    ctx.lineWidth = robot.id === frame.selected ? 3 : 1.5;
    ctx.stroke();
    const [hu, hv] = px(robot.x + 2 * robot.radius * Math.cos(robot.angle), robot.y + 2 * robot.radius * Math.sin(robot.angle));
    ctx.beginPath();
    ctx.moveTo(u, v);
    ctx.lineTo(hu, hv);
    ctx.stroke();
  }
}

function showFrame(message) {
  frame = message;
  const selected = frame.robots.find((r) => r.id === frame.selected);
  statusLine.textContent = `frame ${frame.frame} · ${frame.time.toFixed(1)} s · ${frame.status}` +
    (selected ? ` · robot ${selected.id}: ${selected.status}` : "");
  document.getElementById("objective").textContent = selected ?
    (selected.objective ? `to ${selected.objective}${selected.reached ? " (reached)" : ""}` :
      selected.status === "interrupted" ? "interrupted" : "no order") : "";
  document.getElementById("string").textContent = frame.string;
  if (selecting !== null && frame.selected === selecting) selecting = null;
  if (selecting === null && String(frame.selected) !== robotSelect.value) robotSelect.value = String(frame.selected);
  const speed = document.getElementById("speed");
  if (document.activeElement !== speed && Number(speed.value) !== frame.speed) {
    if (![...speed.options].some((o) => Number(o.value) === frame.speed)) {
      speed.add(new Option(`${frame.speed}×`, String(frame.speed)));
    }
    speed.value = [...speed.options].find((o) => Number(o.value) === frame.speed).value;
  }
  if (frame.errors && frame.errors.length) showError(frame.errors.join("\n"));
  draw();
}

function connect() {
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  socket = new WebSocket(`${scheme}://${location.host}/ws`);
  socket.onopen = () => { statusLine.textContent = "connected"; };
  socket.onmessage = (event) => {
    const message = JSON.parse(event.data);
    if (message.type === "frame") showFrame(message);
    else if (message.type === "error") showError(message.message);
    else if (message.type === "ok") showError("");
  };
  socket.onclose = (event) => {
    statusLine.textContent = "disconnected";
    showError(`connection closed${event.reason ? ": " + event.reason : ""} (code ${event.code}); reload to reconnect`);
  };
}

function markerAt(u, v) {
  let best = null;
  let bestDistance = 14;  // pixels
  for (const room of world.rooms) {
    const [mu, mv] = px(room.x, room.y);
    const d = Math.hypot(mu - u, mv - v);
    if (d < bestDistance) { best = room; bestDistance = d; }
  }
  return best;
}

function robotAt(u, v) {
  if (!frame) return null;
  for (const robot of frame.robots) {
    const [ru, rv] = px(robot.x, robot.y);
    if (Math.hypot(ru - u, rv - v) < Math.max(8, Math.abs(world.map.ax) * robot.radius)) return robot;
  }
  return null;
}

canvas.addEventListener("click", (event) => {
  const rect = canvas.getBoundingClientRect();
  const u = (event.clientX - rect.left) * canvas.width / rect.width;
  const v = (event.clientY - rect.top) * canvas.height / rect.height;
  const room = markerAt(u, v);
  if (room) { send({ type: "order", robot: Number(robotSelect.value), room: room.name }); return; }
  const robot = robotAt(u, v);
  if (robot) select(robot.id);
});

for (const name of ["pause", "resume", "step", "reset"]) {
  document.getElementById(name).addEventListener("click", () => send({ type: name }));
}
document.getElementById("speed").addEventListener("change", (e) => {
  send({ type: "speed", value: Number(e.target.value) });
  e.target.blur();  // from now on the menu shows the speed the server runs at
});
function select(id) {
  selecting = id;
  robotSelect.value = String(id);
  send({ type: "select", robot: id });
}
robotSelect.addEventListener("change", () => select(Number(robotSelect.value)));
// Stop: the selected robot's task is interrupted through gObjective (eObjective<marker=-1>).
document.getElementById("cancel").addEventListener("click", () => send({ type: "cancel", robot: Number(robotSelect.value) }));

function refreshImages() {
  if (frame && frame.selected !== null) {
    const camera = document.getElementById("camera");
    const next = new Image();
    next.onload = () => { camera.src = next.src; camera.dataset.robot = String(frame.selected); };
    next.onerror = () => { camera.removeAttribute("src"); camera.alt = `robot ${frame.selected}: no camera image`; };
    next.src = `/api/camera/${frame.selected}.jpg?t=${Date.now()}`;
  }
  const overview = document.getElementById("overview");
  const next3d = new Image();
  next3d.onload = () => { overview.src = next3d.src; };
  next3d.src = `/api/overview.png?t=${Date.now()}`;
}

async function start() {
  world = await (await fetch("/api/world")).json();
  document.getElementById("world-name").textContent = `${world.name} · ${world.planner}`;
  canvas.width = world.map.width;
  canvas.height = world.map.height;
  for (const robot of world.robots) {
    const option = document.createElement("option");
    option.value = String(robot.id);
    option.textContent = `robot ${robot.id}`;
    robotSelect.appendChild(option);
  }
  const rooms = document.getElementById("rooms");
  for (const room of world.rooms) {
    const button = document.createElement("button");
    button.textContent = room.name;
    button.dataset.room = room.name;
    button.addEventListener("click", () => send({ type: "order", robot: Number(robotSelect.value), room: room.name }));
    rooms.appendChild(button);
  }
  mapImage = new Image();
  mapImage.onload = () => { canvas.dataset.drawn = "true"; draw(); };
  mapImage.src = "/api/map.png";
  connect();
  setInterval(refreshImages, 1000);
}

start().catch((e) => showError(`cannot start the viewer: ${e}`));
