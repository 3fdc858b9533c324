#!/usr/bin/env node
// Browser test of the mobot dashboard: a real mobotd (sim backend) and Debian's Chromium driven by
// playwright-core.
//
//   node tests/web/dashboard.test.mjs --mobotd build/server/mobotd [--headed] [--keep]
//
// Starts `mobotd --backend sim --port 0 --time-scale 1 --data-dir <tmp> --token <random>`, opens
// the dashboard, and checks: map + laser drawn, keyboard teleop moves the robot, e-stop engages
// (and teleop is refused meanwhile), goal navigation (press + drag on the map sends a goal with a
// heading, the path is drawn, the robot reaches the point at 5x sim speed; a goal in a wall shows
// goal_in_obstacle; a plain click sends no heading and Cancel cancels; the EKF uncertainty and the
// truth ghost are drawn), sim tools (drop and remove an obstacle, set the initial pose), the Maps
// and Runs tabs list items, the 3D tab (three.js view; a 10 s / 1 deg sweep from the "3D sweep"
// button: the progress bar advances, the cloud is drawn, the PLY downloads) and the "3D obstacles"
// (IPaBD) overlay on the Live map, a wrong token shows an auth error, stopping the server shows
// "disconnected" and a restarted server is reconnected. At 1400 px the status panel shows the
// localization method and the velocities whole, and the sweep's bar is full when it reads 100 %
// (element boxes measured). mapping_steps.mjs adds keep-out zones, global localization with the
// particle cloud and the mapping workflow; each skips, saying why, on a server without its path.
// camera_steps.mjs adds the camera panel, tracking and following against a second mobotd started
// with deploy/config/camera_robot.yaml when that file exists (skipped, saying why, when GET
// /api/v1/camera answers 404). operator_steps.mjs adds the operator lock (the Operator card, a
// second token "bob" taking the lock, an admin take-over, two browser contexts contending) and the
// admins' Connected list (skipped, saying why, when GET /api/v1/operator answers 404).
// link_steps.mjs adds the login view (a wrong token refused with nothing loaded, a good one with its
// role, Sign out, "remember me", a ?token= URL used once), the Link card's latency plot, and,
// through link_proxy.mjs (an impairing TCP proxy in front of mobotd), the disconnect banner when
// the link is cut and gone once it is back, teleop and round trips with 150 ms added each way, and
// a 4401 close (token revoked) that sends the page to the login view.
// Exit code 0 when every check passes (skips pass). Screenshots of failures go to tests/web/out/.

import { spawn } from 'node:child_process';
import { randomBytes } from 'node:crypto';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { cameraSteps, REPO_ROOT } from './camera_steps.mjs';
import { mappingLocalizationZoneSteps, Skip } from './mapping_steps.mjs';
import { linkSteps } from './link_steps.mjs';
import { operatorSteps } from './operator_steps.mjs';
import { restProbe } from './rest_probe.mjs';

const HERE = dirname(fileURLToPath(import.meta.url));
const OUT_DIR = join(HERE, 'out');
const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
// The mapping, localization and zone scenarios add about 40 s once the server has them (more on a
// loaded machine), the camera scenarios (a second mobotd) about 30 s, the operator lock's (three more
// browser contexts) about 30 s, the login and link scenarios (four contexts, a proxy) about 25 s.
const TOTAL_BUDGET_MS = 250_000;

// ---------------------------------------------------------------- arguments

function parseArgs(argv) {
  const args = { mobotd: process.env.MOBOTD || '', headed: false, keep: false };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--mobotd') args.mobotd = argv[++i] ?? '';
    else if (a.startsWith('--mobotd=')) args.mobotd = a.slice('--mobotd='.length);
    else if (a === '--headed') args.headed = true;
    else if (a === '--keep') args.keep = true;
    else if (a === '-h' || a === '--help') {
      console.log('usage: node tests/web/dashboard.test.mjs --mobotd PATH_TO_MOBOTD [--headed] [--keep]');
      process.exit(0);
    } else {
      console.error(`unknown argument: ${a}`);
      process.exit(2);
    }
  }
  if (!args.mobotd) {
    console.error('usage: node tests/web/dashboard.test.mjs --mobotd PATH_TO_MOBOTD');
    process.exit(2);
  }
  args.mobotd = resolve(args.mobotd);
  if (!existsSync(args.mobotd)) {
    console.error(`mobotd not found at ${args.mobotd} (build it first)`);
    process.exit(2);
  }
  if (!existsSync(CHROMIUM)) {
    console.error(`Chromium not found at ${CHROMIUM} (apt-get install chromium)`);
    process.exit(2);
  }
  return args;
}

// ---------------------------------------------------------------- mobotd

/**
 * Starts mobotd and resolves once it printed `mobotd listening on http://ADDR:PORT`. `extraArgs`
 * (e.g. --config) go after the test's own; `cwd` (default: this process's) is where relative paths
 * in them resolve.
 */
function startServer(mobotd, { dataDir, token, port = 0, extraArgs = [], cwd = undefined }) {
  const argv = ['--backend', 'sim', '--port', String(port), '--time-scale', '1', '--data-dir', dataDir, '--token', token, ...extraArgs];
  const child = spawn(mobotd, argv, { stdio: ['ignore', 'pipe', 'pipe'], cwd });
  const log = [];
  const remember = (line) => {
    log.push(line);
    if (log.length > 200) log.shift();
  };
  createInterface({ input: child.stderr }).on('line', remember);
  const exited = new Promise((res) => child.once('exit', (code, signal) => res({ code, signal })));
  const ready = new Promise((res, rej) => {
    const timer = setTimeout(() => rej(new Error(`mobotd did not print its listening line within 15 s\n${log.slice(-20).join('\n')}`)), 15_000);
    createInterface({ input: child.stdout }).on('line', (line) => {
      remember(line);
      const match = /^mobotd listening on (http:\/\/\S+?)\/?$/.exec(line.trim());
      if (match) {
        clearTimeout(timer);
        res(match[1]);
      }
    });
    exited.then(({ code, signal }) => {
      clearTimeout(timer);
      rej(new Error(`mobotd exited early (code ${code}, signal ${signal})\n${log.slice(-20).join('\n')}`));
    });
  });
  return { child, ready, exited, log, argv };
}

async function stopServer(server, timeoutMs = 8000) {
  if (!server || server.child.exitCode !== null || server.child.signalCode !== null) return server?.exited;
  server.child.kill('SIGTERM');
  const timer = setTimeout(() => server.child.kill('SIGKILL'), timeoutMs);
  const result = await server.exited;
  clearTimeout(timer);
  return result;
}

// ---------------------------------------------------------------- helpers

/** A binary PGM (P5): free inside, an occupied border. */
function makePgm(width, height) {
  const header = Buffer.from(`P5\n${width} ${height}\n255\n`, 'ascii');
  const pixels = Buffer.alloc(width * height, 254);
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      if (x === 0 || y === 0 || x === width - 1 || y === height - 1) pixels[y * width + x] = 0;
    }
  }
  return Buffer.concat([header, pixels]);
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function rest(base, token, method, path, body) {
  const { status, json, text } = await restProbe(base, token, method, path, body);
  if (status < 200 || status > 299) throw new Error(`${method} ${path} -> ${status} ${text.slice(0, 200)}`);
  return json;
}

async function until(what, fn, timeoutMs = 5000, intervalMs = 100) {
  const deadline = Date.now() + timeoutMs;
  let last;
  for (;;) {
    try {
      last = await fn();
      if (last) return last;
    } catch (error) {
      last = error;
    }
    if (Date.now() > deadline) {
      throw new Error(`timed out after ${timeoutMs} ms waiting for ${what}${last instanceof Error ? ` (${last.message})` : ''}`);
    }
    await sleep(intervalMs);
  }
}

/** Screen (viewport) position of a map-frame point, from the app's view transform. */
const toClient = (page, x, y) => page.evaluate(([mx, my]) => window.__mobot.mapToClient(mx, my), [x, y]);

/** Press at map point `at`, drag to map point `to` (null: a plain click), `during()`, release. */
async function pressDrag(page, at, to, during) {
  const [x0, y0] = await toClient(page, at.x, at.y);
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  if (to) {
    const [x1, y1] = await toClient(page, to.x, to.y);
    await page.mouse.move((x0 + x1) / 2, (y0 + y1) / 2, { steps: 4 });
    await page.mouse.move(x1, y1, { steps: 4 });
  }
  if (during) await during();
  await page.mouse.up();
}

const angleDiff = (a, b) => Math.abs(Math.atan2(Math.sin(a - b), Math.cos(a - b)));

async function screenshot(page, name) {
  mkdirSync(OUT_DIR, { recursive: true });
  const file = join(OUT_DIR, name);
  await page.screenshot({ path: file });
  return file;
}

const hooks = (page) => page.evaluate(() => {
  const m = window.__mobot;
  return m
    ? {
        connected: m.connected,
        connection: m.connection,
        scansDrawn: m.scansDrawn,
        framesDrawn: m.framesDrawn,
        poseCount: m.poseCount,
        lastPose: m.lastPose,
        mapShown: m.mapShown,
        robotVisible: m.robotVisible,
        lastGoal: m.lastGoal,
        pathPoints: m.pathPoints,
        goalError: m.goalError,
        mapMode: m.mapMode,
        estop: m.estop,
        lastError: m.lastError,
        reconnects: m.reconnects,
      }
    : null;
});

// ---------------------------------------------------------------- test runner

const results = [];
let currentPage = null;

async function step(name, fn) {
  const started = Date.now();
  try {
    const note = await fn();
    const ms = Date.now() - started;
    results.push({ name, ok: true });
    console.log(`  ✓ ${name} (${ms} ms)${note ? ` — ${note}` : ''}`);
    return true;
  } catch (error) {
    const ms = Date.now() - started;
    if (error instanceof Skip) {
      results.push({ name, ok: true, skipped: true });
      console.log(`  - ${name} (${ms} ms) — skipped: ${error.message}`);
      return true;
    }
    results.push({ name, ok: false, error });
    console.log(`  ✗ ${name} (${ms} ms)\n      ${String(error?.stack || error).split('\n').join('\n      ')}`);
    if (currentPage) {
      const file = join(OUT_DIR, `fail-${results.length}-${name.replace(/[^a-z0-9]+/gi, '-').toLowerCase()}.png`);
      try {
        mkdirSync(OUT_DIR, { recursive: true });
        await currentPage.screenshot({ path: file });
        console.log(`      screenshot: ${file}`);
      } catch (shotError) {
        console.log(`      (no screenshot: ${shotError.message})`);
      }
    }
    return false;
  }
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const token = randomBytes(18).toString('hex');
  const dataDir = mkdtempSync(join(tmpdir(), 'mobot-web-test-'));
  let server = null;
  /** Other mobotd processes (the camera robot's), killed with the main one should the budget run out. */
  const extraServers = new Set();
  let browser = null;
  const pageErrors = [];
  const t0 = Date.now();
  const budget = setTimeout(() => {
    console.error(`\nFAIL: the browser test exceeded its ${TOTAL_BUDGET_MS / 1000} s budget`);
    if (server) server.child.kill('SIGKILL');
    for (const extra of extraServers) extra.child.kill('SIGKILL');
    process.exit(1);
  }, TOTAL_BUDGET_MS + 15_000);

  rmSync(OUT_DIR, { recursive: true, force: true });
  console.log(`mobot dashboard test\n  mobotd:   ${args.mobotd}\n  chromium: ${CHROMIUM}\n  data dir: ${dataDir}`);
  try {
    server = startServer(args.mobotd, { dataDir, token });
    let base = await server.ready;
    const port = Number(new URL(base).port);
    console.log(`  server:   ${base}`);

    // The dashboard must be built and served (GET / without a token).
    const index = await fetch(`${base}/`);
    if (!index.ok) {
      const text = await index.text();
      throw new Error(`GET / -> ${index.status}: ${text.slice(0, 300)}\n(build the dashboard: cd web && npm ci && npm run build)`);
    }

    // The default launch runs on a fresh temporary profile; every context has its own storage.
    browser = await chromium.launch({
      executablePath: CHROMIUM,
      headless: !args.headed,
      args: [
        ...(args.headed ? [] : ['--headless']),
        '--no-sandbox',
        '--disable-gpu',
        '--disable-quic',
        '--no-first-run',
        '--disable-background-networking',
        '--disable-component-update',
        '--disable-sync',
      ],
    });
    const context = await browser.newContext({ viewport: { width: 1440, height: 900 } });
    const page = await context.newPage();
    currentPage = page;
    page.on('pageerror', (error) => pageErrors.push(String(error)));
    page.on('console', (message) => {
      if (message.type() === 'error' && !/WebSocket connection|Failed to load resource/.test(message.text())) {
        pageErrors.push(`console: ${message.text()}`);
      }
    });

    await step('dashboard loads and the stream connects', async () => {
      await page.goto(`${base}/?token=${token}`, { waitUntil: 'domcontentloaded' });
      await page.waitForFunction(() => window.__mobot && window.__mobot.connected, null, { timeout: 10_000 });
      const url = new URL(page.url());
      if (url.searchParams.has('token')) throw new Error('the token stays in the address bar');
    });

    await step('map shown and laser scans drawn', async () => {
      await page.waitForFunction(() => window.__mobot.mapShown && window.__mobot.scansDrawn > 3, null, { timeout: 10_000 });
      if (await page.isVisible('[data-testid=map-empty]')) throw new Error('the "waiting for the map" note is still shown');
      const h = await hooks(page);
      if (!h.robotVisible) throw new Error('the robot is outside the visible map view');
      return `${h.scansDrawn} scans, ${h.poseCount} poses, ${h.framesDrawn} frames drawn`;
    });

    await step('status panel shows mode, pose, sensors and link stats', async () => {
      await page.waitForFunction(() => {
        const text = (id) => document.querySelector(`[data-testid=${id}]`)?.textContent?.trim() ?? '';
        return text('status-mode') !== '–' && text('status-mode') !== '' && text('status-pose').startsWith('x ') &&
          document.querySelectorAll('[data-testid=status-sensors] .sensor').length > 0 &&
          document.querySelector('[data-testid=topic-pose]') !== null && text('latency-rtt').endsWith('ms');
      }, null, { timeout: 6000 });
      const mode = await page.textContent('[data-testid=status-mode]');
      const rtt = await page.textContent('[data-testid=latency-rtt]');
      return `mode ${mode}, rtt ${rtt}`;
    });

    await step('at 1400 px the status panel shows the localization method and the velocities whole', async () => {
      await page.setViewportSize({ width: 1400, height: 900 });
      try {
        const robot = await rest(base, token, 'GET', '/api/v1/robot');
        // Turning right in place gives a negative w: the widest velocity text ("w -1.00 rad/s").
        await page.locator('[data-testid=map-canvas]').hover();
        await page.keyboard.down('d');
        await page.waitForFunction(() => /w -\d/.test(document.querySelector('[data-testid=status-velocity]')?.textContent ?? ''), null, { timeout: 3000 });
        const boxes = await page.evaluate(() => ['status-localization', 'status-velocity', 'status-pose', 'status-sigma'].map((id) => {
          const el = document.querySelector(`[data-testid=${id}]`);
          const card = el.closest('.card').getBoundingClientRect();
          const box = el.getBoundingClientRect();
          // Every text piece of the value (the parts, the method's detail), as the browser laid it out.
          const range = document.createRange();
          range.selectNodeContents(el);
          const rects = [...range.getClientRects()];
          return {
            id,
            text: el.textContent.replace(/\s+/g, ' ').trim(),
            scrollWidth: el.scrollWidth,
            clientWidth: el.clientWidth,
            box: { left: box.left, right: box.right },
            card: { left: card.left, right: card.right },
            textRight: Math.max(...rects.map((r) => r.right)),
            textLeft: Math.min(...rects.map((r) => r.left)),
          };
        }));
        await page.keyboard.up('d');
        for (const b of boxes) {
          if (b.scrollWidth > b.clientWidth + 1) throw new Error(`${b.id} "${b.text}" overflows: ${b.scrollWidth} px of content in ${b.clientWidth} px`);
          if (b.textRight > b.box.right + 0.5 || b.textLeft < b.box.left - 0.5) throw new Error(`${b.id} "${b.text}" is laid out past its box: ${JSON.stringify(b)}`);
          if (b.box.right > b.card.right + 0.5) throw new Error(`${b.id} ends past the status card: ${JSON.stringify(b)}`);
        }
        const loc = boxes.find((b) => b.id === 'status-localization');
        const detail = /\((.*)\)/.exec(robot.localization.method)?.[1] ?? '';
        if (detail && !loc.text.includes(detail)) throw new Error(`the localization row reads "${loc.text}", /robot says "${robot.localization.method}"`);
        const vel = boxes.find((b) => b.id === 'status-velocity');
        if (!/^v -?\d+\.\d\d m\/s w -\d+\.\d\d rad\/s$/.test(vel.text)) throw new Error(`the velocity row reads "${vel.text}"`);
        await screenshot(page, 'status-1400.png');
        // Turn back about as far.
        await page.keyboard.down('a');
        await sleep(700);
        await page.keyboard.up('a');
        return `"${loc.text}" and "${vel.text}" inside ${Math.round(vel.box.right - vel.box.left)} px`;
      } finally {
        await page.keyboard.up('d');
        await page.setViewportSize({ width: 1440, height: 900 });
      }
    });

    await step("holding 'w' drives the robot forward (> 0.2 m)", async () => {
      const before = await rest(base, token, 'GET', '/api/v1/robot');
      const hookBefore = (await hooks(page)).lastPose;
      await page.locator('[data-testid=map-canvas]').hover();
      await page.keyboard.down('w');
      await sleep(1500);
      const driving = await page.textContent('[data-testid=teleop-cmd]');
      await page.keyboard.up('w');
      const after = await rest(base, token, 'GET', '/api/v1/robot');
      const moved = Math.hypot(after.pose.x - before.pose.x, after.pose.y - before.pose.y);
      const hookAfter = (await hooks(page)).lastPose;
      const movedInPage = hookBefore && hookAfter ? Math.hypot(hookAfter.x - hookBefore.x, hookAfter.y - hookBefore.y) : NaN;
      if (!(moved > 0.2)) {
        throw new Error(`the robot moved ${moved.toFixed(3)} m (REST), ${movedInPage.toFixed(3)} m (page); teleop panel said "${driving}"`);
      }
      if (!/keyboard/.test(driving ?? '')) throw new Error(`teleop panel said "${driving}" while 'w' was held`);
      // Releasing the key sends one zero command: the robot comes to rest.
      await until('the robot to stop after the key is released', async () => {
        const r = await rest(base, token, 'GET', '/api/v1/robot');
        return Math.abs(r.velocity.v) < 0.05;
      }, 3000, 150);
      return `moved ${moved.toFixed(2)} m (page saw ${movedInPage.toFixed(2)} m)`;
    });

    await step('e-stop button engages the e-stop (on the stream); teleop is refused meanwhile', async () => {
      await page.click('[data-testid=estop]');
      await until('GET /api/v1/robot to report estop true', async () => (await rest(base, token, 'GET', '/api/v1/robot')).estop === true, 3000);
      await page.waitForSelector('[data-testid=estop-state][data-engaged=true]', { timeout: 3000 });
      const ack = await page.evaluate(() => window.__mobot.estopAck);
      if (ack?.via !== 'stream' || ack.engaged !== true) throw new Error(`the e-stop was acknowledged ${JSON.stringify(ack)}, expected on the stream`);
      await page.keyboard.down('w');
      await sleep(300);
      await page.keyboard.up('w');
      await page.waitForFunction(() => /estop_engaged/.test(window.__mobot.lastError ?? ''), null, { timeout: 3000 });
      await page.waitForSelector('[data-testid=toast-error]', { timeout: 2000 });
      return `acknowledged on the stream in ${ack.elapsedMs.toFixed(0)} ms`;
    });

    await step('release button releases the e-stop', async () => {
      await page.click('[data-testid=estop-release]');
      await until('GET /api/v1/robot to report estop false', async () => (await rest(base, token, 'GET', '/api/v1/robot')).estop === false, 3000);
      await page.waitForSelector('[data-testid=estop-state][data-engaged=false]', { timeout: 3000 });
    });

    await step('goal panel, sim tools and legend are shown; the goal list is loaded', async () => {
      await page.waitForSelector('[data-testid=goal-panel]', { state: 'visible', timeout: 3000 });
      await page.waitForSelector('[data-testid=sim-panel]', { state: 'visible', timeout: 3000 });
      await page.waitForSelector('[data-testid=map-legend]', { state: 'visible', timeout: 3000 });
      const status = (await page.textContent('[data-testid=goal-status]'))?.trim();
      const options = await page.$$eval('[data-testid=goal-controller] option', (els) => els.map((e) => `${e.value}${e.disabled ? '(off)' : ''}`));
      if (!options.includes('lyapunov')) throw new Error(`controller options: ${options.join(', ')}`);
      const planners = await page.$$eval('[data-testid=goal-planner] option', (els) => els.map((e) => `${e.value}${e.disabled ? '(off)' : ''}`));
      if (!planners.includes('astar') || !planners.includes('voronoi')) throw new Error(`planner options: ${planners.join(', ')}`);
      return `status "${status}", planners ${planners.join(' ')}, controllers ${options.join(' ')}`;
    });

    // Goal navigation runs the simulator 5x faster; the clock goes back to 1x afterwards.
    await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 5 });
    let goalTarget = null;

    await step('Set goal: press + drag on the map sends {x, y, theta}; the path is drawn', async () => {
      await page.click('[data-testid=view-fit]');
      const truth = await rest(base, token, 'GET', '/api/v1/sim/truth');
      // ~3 m east along the office corridor (y = 7.5), heading north (drag towards +y).
      const at = { x: Math.round((truth.pose.x + 3) * 10) / 10, y: 7.5 };
      await page.click('[data-testid=goal-set]');
      if ((await page.evaluate(() => window.__mobot.mapMode)) !== 'goal') throw new Error('the Set goal button did not enter goal mode');
      await page.waitForSelector('[data-testid=map-mode]', { state: 'visible', timeout: 3000 });
      const before = (await hooks(page)).lastGoal?.id ?? 0;
      await pressDrag(page, at, { x: at.x, y: at.y + 0.8 }, async () => {
        await sleep(50);
        await screenshot(page, 'goal-drag.png');
      });
      await page.waitForFunction((id) => (window.__mobot.lastGoal?.id ?? 0) > id, before, { timeout: 3000 });
      await page.waitForFunction(() => window.__mobot.pathPoints > 1, null, { timeout: 3000 });
      const id = await page.evaluate(() => window.__mobot.lastGoal.id);
      const goal = await rest(base, token, 'GET', `/api/v1/goals/${id}`);
      const clickError = Math.hypot(goal.target.x - at.x, goal.target.y - at.y);
      if (clickError > 0.05) throw new Error(`the goal target (${goal.target.x}, ${goal.target.y}) is ${clickError.toFixed(3)} m from the pressed point (${at.x}, ${at.y})`);
      if (typeof goal.target.theta !== 'number' || angleDiff(goal.target.theta, Math.PI / 2) > 0.05) {
        throw new Error(`the dragged heading was sent as ${goal.target.theta} (expected ~pi/2)`);
      }
      if ((await hooks(page)).mapMode !== null) throw new Error('goal mode is still active after the goal was sent');
      await page.waitForFunction(() => /^(planning|active|succeeded)$/.test(document.querySelector('[data-testid=goal-status]')?.textContent?.trim() ?? ''), null, { timeout: 2000 });
      await sleep(700);
      await screenshot(page, 'goal-active.png');
      goalTarget = { id, x: goal.target.x, y: goal.target.y, theta: goal.target.theta, pressed: at };
      return `goal #${id} at (${goal.target.x.toFixed(2)}, ${goal.target.y.toFixed(2)}, ${goal.target.theta.toFixed(2)}), ${await page.evaluate(() => window.__mobot.pathPoints)} path points`;
    });

    await step('the goal succeeds: the robot stops within 0.15 m of the clicked point at the heading', async () => {
      if (!goalTarget) throw new Error('no goal was sent');
      const t0 = Date.now();
      await page.waitForFunction(
        (id) => window.__mobot.lastGoal?.id === id && /^(succeeded|failed|canceled)$/.test(window.__mobot.lastGoal.status),
        goalTarget.id,
        { timeout: 25_000, polling: 100 },
      );
      const last = await page.evaluate(() => window.__mobot.lastGoal);
      if (last.status !== 'succeeded') throw new Error(`goal #${last.id} ended ${last.status} (${last.reason})`);
      await page.waitForSelector('[data-testid=goal-status][data-status=succeeded]', { timeout: 2000 });
      const panelText = (await page.textContent('[data-testid=goal-status]'))?.trim();
      if (panelText !== 'succeeded') throw new Error(`the goal panel shows "${panelText}"`);
      const truth = await rest(base, token, 'GET', '/api/v1/sim/truth');
      const offTarget = Math.hypot(truth.pose.x - goalTarget.pressed.x, truth.pose.y - goalTarget.pressed.y);
      const offHeading = angleDiff(truth.pose.theta, goalTarget.theta);
      if (offTarget > 0.15) throw new Error(`the true pose (${truth.pose.x.toFixed(3)}, ${truth.pose.y.toFixed(3)}) is ${offTarget.toFixed(3)} m from the clicked point`);
      if (offHeading > 0.15) throw new Error(`the true heading ${truth.pose.theta.toFixed(3)} is ${offHeading.toFixed(3)} rad from the requested ${goalTarget.theta.toFixed(3)}`);
      if (truth.collisions > 0) throw new Error(`${truth.collisions} collision(s) on the way`);
      const history = await page.locator('[data-testid=goal-history-item][data-status=succeeded]').count();
      if (history < 1) throw new Error('the succeeded goal is not in the recent goals list');
      await screenshot(page, 'goal-succeeded.png');
      return `in ${((Date.now() - t0) / 1000).toFixed(1)} s wall; truth ${offTarget.toFixed(3)} m / ${offHeading.toFixed(3)} rad off; remaining ${(await page.textContent('[data-testid=goal-remaining]'))?.trim()}`;
    });

    await step('the EKF pose is drawn with its covariance (status shows the sigmas)', async () => {
      const pose = (await hooks(page)).lastPose;
      const sigma = (await page.textContent('[data-testid=status-sigma]'))?.trim() ?? '';
      if (!/^x [\d.]+ (mm|cm) y [\d.]+ (mm|cm) θ [\d.]+°$/.test(sigma)) throw new Error(`uncertainty row shows "${sigma}"`);
      return `${sigma}; EKF at (${pose.x.toFixed(2)}, ${pose.y.toFixed(2)})`;
    });

    await step('a goal inside a wall (key G, click) shows goal_in_obstacle', async () => {
      await page.locator('[data-testid=map-canvas]').hover();
      await page.keyboard.press('g');
      if ((await page.evaluate(() => window.__mobot.mapMode)) !== 'goal') throw new Error('the G key did not enter goal mode');
      const before = (await hooks(page)).lastGoal?.id;
      // The corridor's south wall: y 6.35..6.5.
      await pressDrag(page, { x: 6.0, y: 6.43 }, null);
      await page.waitForSelector('[data-testid=goal-error]:has-text("goal_in_obstacle")', { state: 'visible', timeout: 3000 });
      const error = await page.evaluate(() => window.__mobot.goalError);
      if (error?.code !== 'goal_in_obstacle' || error.status !== 422) throw new Error(`goalError is ${JSON.stringify(error)}`);
      const after = (await hooks(page)).lastGoal?.id;
      if (after !== before) throw new Error(`a refused goal changed the current goal (#${before} -> #${after})`);
      await screenshot(page, 'goal-refused.png');
      return (await page.textContent('[data-testid=goal-error]'))?.replace(/\s+/g, ' ').trim();
    });

    await step('a plain click sends a goal without heading; Cancel cancels it', async () => {
      // At 1x: at 5x the robot may reach the goal before a loaded machine gets to Cancel.
      await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 1 });
      try {
        await page.click('[data-testid=goal-set]');
        const before = (await hooks(page)).lastGoal?.id ?? 0;
        await pressDrag(page, { x: 12.0, y: 7.5 }, null);
        await page.waitForFunction((id) => (window.__mobot.lastGoal?.id ?? 0) > id, before, { timeout: 3000 });
        if (await page.isVisible('[data-testid=goal-error]')) throw new Error('the earlier error is still shown after a goal was accepted');
        const id = await page.evaluate(() => window.__mobot.lastGoal.id);
        const goal = await rest(base, token, 'GET', `/api/v1/goals/${id}`);
        if ('theta' in goal.target) throw new Error(`a plain click sent theta ${goal.target.theta}`);
        await page.waitForSelector('[data-testid=goal-cancel]:not([disabled])', { timeout: 3000 });
        await page.click('[data-testid=goal-cancel]');
        await page.waitForSelector('[data-testid=goal-status][data-status=canceled]', { timeout: 3000 });
        const after = await rest(base, token, 'GET', `/api/v1/goals/${id}`);
        if (after.status !== 'canceled') throw new Error(`GET /goals/${id} says ${after.status}`);
        return `goal #${id} ${after.status}${after.reason ? ` (${after.reason})` : ''}`;
      } finally {
        await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 5 });
      }
    });

    await step('sim tools: drop an obstacle (listed and drawn), remove it; set the initial pose', async () => {
      await page.click('[data-testid=sim-obstacle]');
      await pressDrag(page, { x: 14.0, y: 7.5 }, null);
      const item = page.locator('[data-testid=sim-obstacle-item]').first();
      await item.waitFor({ timeout: 3000 });
      const obstacles = await page.evaluate(() => window.__mobot.obstacles);
      if (obstacles.length !== 1 || Math.hypot(obstacles[0].x - 14, obstacles[0].y - 7.5) > 0.05 || obstacles[0].radius !== 0.25) {
        throw new Error(`obstacles: ${JSON.stringify(obstacles)}`);
      }
      await screenshot(page, 'sim-obstacle.png');
      await item.locator('[data-testid=sim-obstacle-remove]').click();
      await item.waitFor({ state: 'detached', timeout: 3000 });
      // Set the initial pose where the robot truly is, heading from a drag. The sim runs at 0.1x so
      // the re-initialised covariance (0.25 m) may be seen before the EKF shrinks it: it often
      // collapses within the first tick or two, so seeing it is reported, not required.
      await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 0.1 });
      const truth = await rest(base, token, 'GET', '/api/v1/sim/truth');
      const heading = truth.pose.theta;
      await page.click('[data-testid=view-robot]');
      await page.click('[data-testid=view-zoom-in]');
      await page.click('[data-testid=view-zoom-in]');
      await page.click('[data-testid=sim-pose]');
      const sawLarge = page
        .waitForFunction(
          () => ((window.__mobot.uncertainty?.major ?? 0) > 0.2 ? window.__mobot.uncertainty : null),
          null,
          { timeout: 2500, polling: 'raf' },
        )
        .then((handle) => handle.jsonValue(), () => null);
      await pressDrag(page, truth.pose, { x: truth.pose.x + 0.8 * Math.cos(heading), y: truth.pose.y + 0.8 * Math.sin(heading) });
      const large = await sawLarge;
      if (large) await screenshot(page, 'uncertainty.png');
      await page.waitForSelector('[data-testid=toast]:has-text("Localization re-initialised")', { timeout: 3000 });
      // Whatever its size, the drawn ellipse is the 2-sigma ellipse of the latest pose's x-y block.
      const drawn = await page.evaluate(() => {
        const m = window.__mobot;
        return { u: m.uncertainty, layer: document.querySelector('#layer-cov')?.checked };
      });
      if (!drawn.u || !drawn.layer || !(drawn.u.major >= drawn.u.minor) || !(drawn.u.sigmaTheta >= 0)) {
        throw new Error(`uncertainty not drawn: ${JSON.stringify(drawn)}`);
      }
      const robot = await rest(base, token, 'GET', '/api/v1/robot');
      const off = Math.hypot(robot.pose.x - truth.pose.x, robot.pose.y - truth.pose.y);
      if (off > 0.1) throw new Error(`the EKF pose is ${off.toFixed(3)} m from where it was set`);
      await page.click('[data-testid=view-fit]');
      const seen = large ? `re-initialised 2σ ellipse ${large.major.toFixed(2)} x ${large.minor.toFixed(2)} m, σθ ${large.sigmaTheta.toFixed(3)} rad seen` : 'the EKF shrank the re-initialised covariance before a frame showed it';
      return `obstacle #${obstacles[0].id} dropped and removed; pose set ${off.toFixed(3)} m from truth; ${seen}`;
    });

    await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 1 });

    await step('Maps tab lists at least one map with a thumbnail', async () => {
      await page.click('[data-testid=tab-maps]');
      await page.waitForSelector('[data-testid=map-item]', { timeout: 5000 });
      const count = await page.locator('[data-testid=map-item]').count();
      await page.waitForSelector('[data-testid=map-item] .thumb img', { timeout: 5000 });
      return `${count} map(s)`;
    });

    await step('Maps tab: import a PGM, refuse to delete the active map (409), delete the import', async () => {
      const name = `web-test-${Date.now() % 100000}`;
      await page.setInputFiles('[data-testid=import-file]', { name: `${name}.pgm`, mimeType: 'image/x-portable-graymap', buffer: makePgm(40, 30) });
      await page.fill('[data-testid=import-name]', name);
      await page.fill('[data-testid=import-resolution]', '0.1');
      await page.click('[data-testid=import-submit]');
      const card = page.locator('[data-testid=map-item]', { hasText: name });
      await card.waitFor({ timeout: 5000 });
      const stored = (await rest(base, token, 'GET', '/api/v1/maps')).find((m) => m.name === name);
      if (!stored || stored.width !== 40 || stored.height !== 30) throw new Error(`imported map not stored as 40x30: ${JSON.stringify(stored)}`);
      page.once('dialog', (dialog) => void dialog.accept());
      await page.locator('[data-testid=map-item].active [data-testid=map-delete]').click();
      await page.waitForSelector('[data-testid=toast-error]:has-text("map_active")', { timeout: 3000 });
      page.once('dialog', (dialog) => void dialog.accept());
      await card.locator('[data-testid=map-delete]').click();
      await card.waitFor({ state: 'detached', timeout: 5000 });
      return `imported #${stored.id} and deleted it`;
    });

    await step('Runs tab lists at least one run and draws its trajectory', async () => {
      await page.click('[data-testid=tab-runs]');
      await page.waitForSelector('[data-testid=run-item]', { timeout: 5000 });
      const count = await page.locator('[data-testid=run-item]').count();
      await page.waitForFunction(() => /poses/.test(document.querySelector('[data-testid=run-summary]')?.textContent ?? ''), null, { timeout: 5000 });
      const summary = (await page.textContent('[data-testid=run-summary]'))?.trim();
      // The CSV download is fetched with the bearer header and saved through a blob link.
      const [download] = await Promise.all([
        page.waitForEvent('download', { timeout: 5000 }),
        page.click('[data-testid=run-csv]'),
      ]);
      const csv = readFileSync(await download.path(), 'utf8');
      if (!csv.startsWith('t,x,y,theta')) throw new Error(`the CSV starts with ${JSON.stringify(csv.slice(0, 40))}`);
      return `${count} run(s); ${summary}; CSV ${csv.trim().split('\n').length - 1} rows`;
    });

    // The 3D sweep runs the simulator 5x faster: a 10 s sweep takes ~2 s, slow enough to see the
    // progress bar pass through intermediate values.
    let sweep = null;

    await step('3D tab: the three.js view loads on demand', async () => {
      await page.click('[data-testid=tab-3d]');
      await page.waitForFunction(() => window.__mobot.sweep.viewReady || window.__mobot.sweep.error, null, { timeout: 8000 });
      const state = await page.evaluate(() => window.__mobot.sweep);
      if (!state.viewReady) throw new Error(`the 3D view did not start: ${state.error}`);
      await page.waitForSelector('[data-testid=cloud-view] canvas[data-testid=cloud-canvas]', { timeout: 3000 });
      const scripts = await page.evaluate(() => performance.getEntriesByType('resource').map((e) => e.name).filter((n) => /cloudview/.test(n)));
      if (scripts.length === 0) throw new Error('the 3D view was not loaded as its own chunk');
      return `chunk ${scripts[0].split('/').pop()}`;
    });

    await step('3D sweep (10 s, 1°): the progress bar advances, the cloud is drawn, the sweep ends done', async () => {
      await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 5 });
      try {
        await page.selectOption('[data-testid=sweep-period]', '10');
        await page.selectOption('[data-testid=sweep-step]', '1');
        const before = (await page.evaluate(() => window.__mobot.sweep.id)) ?? 0;
        await page.click('[data-testid=sweep-start]');
        await page.waitForFunction((id) => (window.__mobot.sweep.id ?? 0) > id, before, { timeout: 3000 });
        const id = await page.evaluate(() => window.__mobot.sweep.id);
        const started = await rest(base, token, 'GET', `/api/v1/sweeps/${id}`);
        if (started.mode.period_s !== 10 || started.mode.step_deg !== 1) throw new Error(`the sweep runs in mode ${JSON.stringify(started.mode)}`);
        // Live: part of the cloud is drawn while the sweep runs.
        // While it runs, each poll also notes how far the fill's box is from the value the bar shows
        // (a width transition restarted by each refresh let it lag by a quarter of the track).
        await page.evaluate(() => {
          window.__barLag = { lag: 0, fill: 0, label: '' };
          window.__noteBarLag = () => {
            const track = document.querySelector('[data-testid=sweep-progress]');
            const fill = track.querySelector('.fill').getBoundingClientRect().width / track.clientWidth;
            const lag = Math.abs(Number(track.dataset.progress) - fill);
            if (lag > window.__barLag.lag) window.__barLag = { lag, fill, label: track.textContent.trim() };
          };
        });
        await page.waitForFunction(() => {
          window.__noteBarLag();
          const s = window.__mobot.sweep;
          return s.status === 'running' && s.progress > 0 && s.progress < 1 && s.drawnPoints > 0;
        }, null, { timeout: 10_000, polling: 50 });
        await screenshot(page, 'cloud3d-running.png');
        await page.waitForFunction((sid) => {
          window.__noteBarLag();
          return window.__mobot.sweep.id === sid && /^(done|failed)$/.test(window.__mobot.sweep.status ?? '');
        }, id, { timeout: 25_000, polling: 100 });
        const state = await page.evaluate(() => window.__mobot.sweep);
        if (state.status !== 'done') throw new Error(`sweep #${id} ended ${state.status}: ${state.error}`);
        // The bar refreshes at 10 Hz: it shows 1 a moment after the status changed (on a loaded machine,
        // with the 3D view rendering in software, seconds: 2.8 s measured under a load of 12 on 2 cores).
        await page.waitForSelector('[data-testid=sweep-progress][data-progress="1.0000"]', { timeout: 6000 });
        // At once, not after a pause: the fill covers the whole track when the label reads 100 %.
        const bar = await page.evaluate(() => {
          const track = document.querySelector('[data-testid=sweep-progress]');
          const fill = track.querySelector('.fill');
          const t = track.getBoundingClientRect();
          const f = fill.getBoundingClientRect();
          return { label: track.textContent.trim(), inner: track.clientWidth, fill: f.width, fillLeft: f.left - t.left - track.clientLeft };
        });
        if (!/^100 %/.test(bar.label) || bar.fill < bar.inner - 0.5 || Math.abs(bar.fillLeft) > 0.5) {
          throw new Error(`at "${bar.label}" the fill is ${bar.fill.toFixed(1)} px of a ${bar.inner} px track (from ${bar.fillLeft.toFixed(1)} px)`);
        }
        const lag = await page.evaluate(() => window.__barLag);
        if (lag.lag > 0.01) throw new Error(`the fill lagged the bar's value by ${(lag.lag * 100).toFixed(1)} % of the track (at "${lag.label}" it covered ${(lag.fill * 100).toFixed(1)} %)`);
        const seen = await page.evaluate(() => window.__mobot.sweep.progressSeen);
        const between = seen.filter((p) => p > 0 && p < 1);
        if (between.length < 2 || seen[seen.length - 1] !== 1) throw new Error(`the progress bar showed ${JSON.stringify(seen)}`);
        for (let i = 1; i < seen.length; i++) if (seen[i] < seen[i - 1]) throw new Error(`the progress went back: ${JSON.stringify(seen)}`);
        const info = await rest(base, token, 'GET', `/api/v1/sweeps/${id}`);
        // The drawn count is the canvas container's data-points, set after a render.
        await page.waitForFunction((n) => Number(document.querySelector('[data-testid=cloud-view]')?.dataset.points) === n, info.points, { timeout: 5000 });
        if (!(info.points > 1000)) throw new Error(`sweep #${id} has ${info.points} points`);
        sweep = { id, points: info.points };
        await page.click('[data-testid=cloud-reset-view]');
        await sleep(300);
        await screenshot(page, 'cloud3d.png');
        return `sweep #${id}: ${info.points} points drawn, ${info.mode.scans} scans, progress ${seen.map((p) => p.toFixed(2)).join(' ')}; at 100 % the fill is ${bar.fill.toFixed(0)} of ${bar.inner} px, at most ${(lag.lag * 100).toFixed(2)} % off while running`;
      } finally {
        await rest(base, token, 'PUT', '/api/v1/sim/clock', { time_scale: 1 });
      }
    });

    await step('3D tab: Download PLY saves the cloud (fetched with the bearer header)', async () => {
      if (!sweep) throw new Error('no sweep finished');
      await page.waitForSelector('[data-testid=sweep-ply]:not([disabled])', { timeout: 3000 });
      const [download] = await Promise.all([
        page.waitForEvent('download', { timeout: 5000 }),
        page.click('[data-testid=sweep-ply]'),
      ]);
      const bytes = readFileSync(await download.path());
      const head = bytes.subarray(0, 200).toString('latin1');
      if (!head.startsWith('ply\n')) throw new Error(`the PLY starts with ${JSON.stringify(head.slice(0, 40))}`);
      const vertices = /element vertex (\d+)/.exec(head);
      if (!vertices || Number(vertices[1]) !== sweep.points) throw new Error(`the PLY header says ${vertices?.[0]}, the sweep has ${sweep.points} points`);
      return `${download.suggestedFilename()}: ${bytes.length} bytes, ${vertices[1]} vertices`;
    });

    await step('a newly opened 3D page shows the newest finished sweep (GET /sweeps, cloud?format=bin)', async () => {
      if (!sweep) throw new Error('no sweep finished');
      const fresh = await context.newPage();
      fresh.on('pageerror', (error) => pageErrors.push(`3D page: ${error}`));
      try {
        // A new tab has none of this tab's sessionStorage: the token comes with the URL.
        await fresh.goto(`${base}/?token=${token}#3d`, { waitUntil: 'domcontentloaded' });
        await fresh.waitForFunction((n) => Number(document.querySelector('[data-testid=cloud-view]')?.dataset.points) === n, sweep.points, { timeout: 8000 });
        const state = await fresh.evaluate(() => window.__mobot.sweep);
        if (state.id !== sweep.id || state.status !== 'done') throw new Error(`the page shows ${JSON.stringify(state)}`);
        return `sweep #${state.id}: ${state.drawnPoints} points drawn`;
      } finally {
        await fresh.close();
      }
    });

    await step('Live tab: the "3D obstacles" toggle draws the IPaBD map of the sweep over the 2D map', async () => {
      if (!sweep) throw new Error('no sweep finished');
      await page.click('[data-testid=tab-live]');
      // The toasts of the sweep sit over the map toolbar: dismiss them (a click removes one).
      await page.$$eval('#toasts .toast', (els) => els.forEach((e) => e.click()));
      const grid = await rest(base, token, 'GET', `/api/v1/sweeps/${sweep.id}/obstacle_map`);
      const occupied = grid.data.filter((v) => v >= 50 && v <= 100).length;
      if (!(occupied > 0)) throw new Error(`the obstacle map of sweep #${sweep.id} has no occupied cell`);
      await page.check('[data-testid=layer-ipabd]');
      await page.waitForFunction((n) => Number(document.querySelector('[data-testid=map-canvas]')?.dataset.ipabdCells) === n, occupied, { timeout: 5000 });
      await page.waitForSelector('[data-testid=map-legend] .ipabd-only', { state: 'visible', timeout: 1000 });
      await screenshot(page, 'ipabd-overlay.png');
      await page.uncheck('[data-testid=layer-ipabd]');
      await page.waitForFunction(() => document.querySelector('[data-testid=map-canvas]')?.dataset.ipabdCells === '0', null, { timeout: 3000 });
      return `${occupied} occupied cells of ${grid.width}x${grid.height} at ${grid.resolution} m drawn`;
    });

    await step('Live tab again: still connected and drawing', async () => {
      await page.click('[data-testid=tab-live]');
      const before = (await hooks(page)).scansDrawn;
      await page.waitForFunction((n) => window.__mobot.connected && window.__mobot.scansDrawn > n + 2, before, { timeout: 5000 });
      if (!(await hooks(page)).robotVisible) throw new Error('the robot is outside the visible map view');
      await screenshot(page, 'live.png');
    });

    await mappingLocalizationZoneSteps({ page, base: () => base, token, step, rest, until, sleep, screenshot, toClient });

    await operatorSteps({ browser, page, base: () => base, token, step, rest, until, sleep, screenshot, pageErrors });

    await linkSteps({ browser, page, base: () => base, token, step, rest, until, sleep, screenshot, pageErrors });

    // The camera robot: a mobotd of its own (same token), started from the repository root so the
    // config's relative paths and web/dist resolve; stopped and its data dir removed afterwards.
    await cameraSteps({
      browser, base: () => base, token, step, rest, until, sleep, screenshot, pageErrors,
      startServer: async (extraArgs) => {
        const extraDir = mkdtempSync(join(tmpdir(), 'mobot-web-camera-'));
        const extra = startServer(args.mobotd, { dataDir: extraDir, token, extraArgs, cwd: REPO_ROOT });
        extraServers.add(extra);
        const stop = async () => {
          const exit = await stopServer(extra);
          extraServers.delete(extra);
          if (!args.keep) rmSync(extraDir, { recursive: true, force: true });
          return exit;
        };
        try {
          const extraBase = await extra.ready;
          console.log(`  camera robot: ${extraBase} (${extraArgs.join(' ')})`);
          return { base: extraBase, log: extra.log, stop };
        } catch (error) {
          await stop();
          throw error;
        }
      },
    });

    await step('a wrong token shows an auth error instead of hanging', async () => {
      const badContext = await browser.newContext({ viewport: { width: 1200, height: 800 } });
      const bad = await badContext.newPage();
      bad.on('pageerror', (error) => pageErrors.push(`bad-token page: ${error}`));
      try {
        await bad.goto(`${base}/?token=wrong-${token.slice(0, 6)}`, { waitUntil: 'domcontentloaded' });
        await bad.waitForSelector('[data-testid=auth-error]', { state: 'visible', timeout: 5000 });
        const state = await bad.evaluate(() => window.__mobot.connection);
        if (state !== 'auth_error') throw new Error(`connection state is ${state}`);
        const message = (await bad.textContent('[data-testid=auth-error]'))?.trim();
        return message;
      } finally {
        await badContext.close();
      }
    });

    await step('a viewer token: teleop, e-stop and 3D sweep refusals are shown', async () => {
      let viewer;
      try {
        viewer = await rest(base, token, 'POST', '/api/v1/tokens', { role: 'viewer', label: 'web test' });
      } catch (error) {
        if (/-> 404/.test(String(error))) return 'skipped: no /api/v1/tokens';
        throw error;
      }
      const viewerContext = await browser.newContext({ viewport: { width: 1200, height: 800 } });
      const vpage = await viewerContext.newPage();
      vpage.on('pageerror', (error) => pageErrors.push(`viewer page: ${error}`));
      try {
        await vpage.goto(`${base}/?token=${viewer.token}`, { waitUntil: 'domcontentloaded' });
        await vpage.waitForFunction(() => window.__mobot && window.__mobot.connected && window.__mobot.scansDrawn > 0, null, { timeout: 8000 });
        await vpage.keyboard.down('w');
        await sleep(250);
        await vpage.keyboard.up('w');
        await vpage.waitForFunction(() => /forbidden/.test(window.__mobot.lastError ?? ''), null, { timeout: 3000 });
        await vpage.click('[data-testid=estop]');
        await vpage.waitForSelector('[data-testid=toast-error]:has-text("E-stop request failed")', { timeout: 3000 });
        const robot = await rest(base, token, 'GET', '/api/v1/robot');
        if (robot.estop) throw new Error('a viewer engaged the e-stop');
        const lastError = (await vpage.evaluate(() => window.__mobot.lastError)) ?? '';
        // A 3D sweep needs the operator role: the 3D page says so above the progress bar.
        const sweepsBefore = (await rest(base, token, 'GET', '/api/v1/sweeps')).length;
        await vpage.click('[data-testid=tab-3d]');
        await vpage.click('[data-testid=sweep-start]');
        await vpage.waitForSelector('[data-testid=sweep-error]:has-text("operator role")', { state: 'visible', timeout: 3000 });
        if ((await rest(base, token, 'GET', '/api/v1/sweeps')).length !== sweepsBefore) throw new Error('a viewer started a sweep');
        return `${lastError}; sweep: ${(await vpage.textContent('[data-testid=sweep-error]'))?.trim()}`;
      } finally {
        await viewerContext.close();
      }
    });

    await step('stopping mobotd (SIGTERM) shows "disconnected"', async () => {
      const exit = await stopServer(server);
      if (exit.code !== 0) throw new Error(`mobotd exited with code ${exit.code} signal ${exit.signal}, expected 0`);
      await page.waitForFunction(() => !window.__mobot.connected, null, { timeout: 5000 });
      await page.waitForFunction(
        () => /disconnected|connecting/.test(document.querySelector('[data-testid=connection]')?.textContent ?? ''),
        null,
        { timeout: 5000 },
      );
      await page.waitForSelector('[data-testid=connection][data-state=disconnected], [data-testid=connection][data-state=connecting]', { timeout: 2000 });
    });

    await step('a restarted mobotd is reconnected and streams again', async () => {
      server = startServer(args.mobotd, { dataDir, token, port });
      base = await server.ready;
      const before = (await hooks(page)).scansDrawn;
      await page.waitForFunction((n) => window.__mobot.connected && window.__mobot.scansDrawn > n + 2, before, { timeout: 10_000 });
      const h = await hooks(page);
      return `reconnected after ${h.reconnects} attempt(s)`;
    });

    await step('no uncaught errors in the page', async () => {
      if (pageErrors.length) throw new Error(pageErrors.slice(0, 10).join('\n'));
    });
  } catch (error) {
    results.push({ name: 'setup', ok: false, error });
    console.log(`  ✗ setup\n      ${String(error?.stack || error).split('\n').join('\n      ')}`);
    if (server?.log?.length) console.log(`  mobotd output (last lines):\n    ${server.log.slice(-15).join('\n    ')}`);
  } finally {
    clearTimeout(budget);
    if (browser) await browser.close().catch(() => {});
    for (const extra of extraServers) await stopServer(extra);
    if (server) {
      const exit = await stopServer(server);
      if (exit && exit.code !== 0 && exit.signal !== 'SIGTERM') console.log(`  note: mobotd exited with code ${exit.code}`);
    }
    if (!args.keep) {
      rmSync(dataDir, { recursive: true, force: true });
    }
  }

  const skipped = results.filter((r) => r.skipped).length;
  const passed = results.filter((r) => r.ok).length - skipped;
  const failed = results.length - passed - skipped;
  const seconds = ((Date.now() - t0) / 1000).toFixed(1);
  console.log(`\n${passed} passed, ${skipped} skipped, ${failed} failed`);
  console.log(`dashboard browser test ${failed === 0 ? 'PASSED' : 'FAILED'} in ${seconds} s`);
  if (Date.now() - t0 > TOTAL_BUDGET_MS) {
    console.log(`note: took longer than the ${TOTAL_BUDGET_MS / 1000} s budget`);
  }
  return failed === 0 ? 0 : 1;
}

main().then(
  (code) => process.exit(code),
  (error) => {
    console.error(error);
    process.exit(1);
  },
);
