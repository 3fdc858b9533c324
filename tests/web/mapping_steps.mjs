// Browser test scenarios of mapping, localization and keep-out zones, run by dashboard.test.mjs
// against its mobotd and page (the same command: node tests/web/dashboard.test.mjs --mobotd ...).
// Each scenario first asks whether the server serves its path; a server that answers 404
// not_found there skips it, with the reason printed, so the suite stays green until the server
// side exists.
//
//   - keep-out zones: draw mode (Esc cancels, fewer than 3 vertices are refused here), a zone drawn
//     by clicks and Enter is stored (GET .../zones has it) and drawn hatched; a crossing polygon
//     closed by a double click shows the server's invalid_polygon message; Delete removes it;
//   - localization: "Localize globally" (202) draws the particle cloud, /robot reports the
//     particle filter and the panel its method and converged flag; the estimator switch goes back
//     to the EKF (PUT /localization/method) and the cloud goes;
//   - mapping: Start mapping, drive by keyboard, the map grows from tiles on the canvas, the live
//     status counts scans, "Localize globally" is refused while mapping, Stop & save refuses an
//     empty name (nothing sent) and saves with one; the map is active, shown whole on the Live
//     map and listed active on the Maps tab.

/** Thrown by a scenario that cannot run on this server; the runner prints the reason. */
export class Skip extends Error {}

/**
 * Whether the server serves `path`: a GET without token is answered 404 not_found for an unknown
 * path before authentication, 401 or 405 for a known one.
 */
export async function served(base, path) {
  const response = await fetch(base + path);
  if (response.status !== 404) return true;
  const text = await response.text();
  return !/"not_found"/.test(text);
}

async function skipUnlessServed(base, path) {
  if (!(await served(base, path))) throw new Skip(`the server answers 404 not_found for ${path}`);
}

/**
 * @param {object} t the runner's context: page, base(), token, step, rest, until, sleep, screenshot,
 *   toClient (map frame -> client pixels)
 */
export async function mappingLocalizationZoneSteps(t) {
  const { page, step, rest, until, sleep, screenshot, toClient } = t;
  const api = (method, path, body) => rest(t.base(), t.token, method, path, body);
  const dismissToasts = () => page.$$eval('#toasts .toast', (els) => els.forEach((e) => e.click()));
  const clickAt = async (x, y) => {
    const [cx, cy] = await toClient(page, x, y);
    await page.mouse.click(cx, cy);
  };

  await step('keep-out zones: draw (Esc cancels, < 3 vertices refused), store with Enter, drawn hatched; a crossing polygon shows invalid_polygon; Delete removes it', async () => {
    const maps = await api('GET', '/api/v1/maps');
    const active = maps.find((m) => m.active);
    if (!active) throw new Error(`no active map: ${JSON.stringify(maps)}`);
    const path = `/api/v1/maps/${active.id}/zones`;
    await skipUnlessServed(t.base(), path);
    await page.click('[data-testid=tab-live]');
    await dismissToasts();
    await page.click('[data-testid=view-fit]');
    await page.waitForFunction((id) => window.__mobot.zones.mapId === id, active.id, { timeout: 6000 });
    const before = await api('GET', path);
    const zoneHook = () => page.evaluate(() => window.__mobot.zones);

    // K enters the draw mode (focus on a button, not a text field); Esc leaves it and sends nothing.
    await page.locator('[data-testid=map-canvas]').hover();
    await page.keyboard.press('k');
    await page.waitForSelector('[data-testid=zone-mode]', { state: 'visible', timeout: 8000 });
    await clickAt(8, 3);
    await clickAt(10, 3);
    await page.keyboard.press('Escape');
    const canceled = await zoneHook();
    if (canceled.drawing || canceled.vertices !== 0) throw new Error(`Esc left the draft ${JSON.stringify(canceled)}`);

    // Two vertices cannot close; two more and Enter store the zone under its name.
    const name = `web-zone-${Date.now() % 100000}`;
    await page.fill('[data-testid=zone-name]', name);
    await page.click('[data-testid=zone-draw]');
    const square = [[8, 3], [10, 3], [10, 4.5], [8, 4.5]];
    await clickAt(...square[0]);
    await clickAt(...square[1]);
    await page.keyboard.press('Enter');
    await page.waitForSelector('[data-testid=zone-error]:has-text("at least 3 vertices")', { state: 'visible', timeout: 5000 });
    if (!(await zoneHook()).drawing) throw new Error('a refused close left the draw mode');
    await clickAt(...square[2]);
    await clickAt(...square[3]);
    await page.keyboard.press('Enter');
    await page.waitForFunction((n) => window.__mobot.zones.count === n, before.length + 1, { timeout: 8000 });
    const stored = await api('GET', path);
    if (stored.length !== before.length + 1) throw new Error(`GET zones lists ${stored.length}, expected ${before.length + 1}`);
    const zone = stored.find((z) => !before.some((b) => b.id === z.id));
    if (!zone || zone.polygon.length !== 4) throw new Error(`the new zone is ${JSON.stringify(zone)}`);
    zone.polygon.forEach(([x, y], i) => {
      const off = Math.hypot(x - square[i][0], y - square[i][1]);
      if (off > 0.05) throw new Error(`vertex ${i} stored at (${x}, ${y}), ${off.toFixed(3)} m from the click at (${square[i]})`);
    });
    if (zone.name !== name) throw new Error(`the zone is named ${JSON.stringify(zone.name)}, not ${name}`);
    await page.waitForFunction((n) => Number(document.querySelector('[data-testid=map-canvas]')?.dataset.zones) === n, stored.length, { timeout: 5000 });
    if ((await zoneHook()).drawing) throw new Error('the draw mode stayed on after the zone was stored');
    await page.waitForSelector(`[data-testid=zone-item][data-id="${zone.id}"]`, { timeout: 5000 });
    await screenshot(page, 'zone.png');

    // A bow tie, closed by a double click on its last vertex: the server refuses it.
    await page.click('[data-testid=zone-draw]');
    const bow = [[12, 2.5], [14, 4.5], [14, 2.5], [12, 4.5]];
    for (const p of bow.slice(0, 3)) await clickAt(...p);
    const [bx, by] = await toClient(page, ...bow[3]);
    await page.mouse.dblclick(bx, by);
    await page.waitForSelector('[data-testid=zone-error]:has-text("invalid_polygon")', { state: 'visible', timeout: 6000 });
    const refused = await zoneHook();
    if (!refused.drawing || refused.vertices !== 4) throw new Error(`after the refusal the draft is ${JSON.stringify(refused)}`);
    if ((await api('GET', path)).length !== stored.length) throw new Error('the crossing polygon was stored');
    await screenshot(page, 'zone-refused.png');
    const message = (await page.textContent('[data-testid=zone-error]'))?.trim();
    await page.keyboard.press('Escape');

    // Delete.
    await page.click(`[data-testid=zone-item][data-id="${zone.id}"] [data-testid=zone-delete]`);
    await page.waitForSelector(`[data-testid=zone-item][data-id="${zone.id}"]`, { state: 'detached', timeout: 6000 });
    const after = await api('GET', path);
    if (after.some((z) => z.id === zone.id)) throw new Error(`zone #${zone.id} is still stored`);
    return `zone #${zone.id} (${zoneSummary(zone)}) stored and deleted; bow tie: ${message}`;
  });

  await step('Localize globally: the particle cloud is drawn, /robot reports the particle filter; the estimator switch goes back to EKF', async () => {
    await skipUnlessServed(t.base(), '/api/v1/localization/global');
    // A server without the particle filter registered refuses the method (400 unknown_method).
    const probe = await fetch(t.base() + '/api/v1/localization/method', {
      method: 'PUT',
      headers: { Authorization: `Bearer ${t.token}`, 'Content-Type': 'application/json' },
      body: JSON.stringify({ method: 'particle_filter' }),
    });
    if (probe.status === 400) throw new Skip('the server has no particle filter (unknown_method)');
    await page.click('[data-testid=tab-live]');
    await dismissToasts();
    await page.click('[data-testid=view-fit]');
    await page.click('[data-testid=loc-global]');
    await page.waitForFunction(() => window.__mobot.particles.drawn > 0, null, { timeout: 8000 });
    const particles = await page.evaluate(() => window.__mobot.particles);
    await until('/robot to report the particle filter', async () => /^particle_filter/.test((await api('GET', '/api/v1/robot')).localization.method), 6000, 150);
    await page.waitForFunction(() => /particle filter/.test(document.querySelector('[data-testid=loc-current]')?.textContent ?? ''), null, { timeout: 6000 });
    // /robot reports converged: the panel shows it (true or false).
    await page.waitForFunction(() => document.querySelector('[data-testid=loc-converged]')?.dataset.converged !== '', null, { timeout: 6000 });
    await screenshot(page, 'particles.png');
    // Drive a little so the filter may converge; reported, not required.
    await page.locator('[data-testid=map-canvas]').hover();
    await page.keyboard.down('a');
    await sleep(1500);
    await page.keyboard.up('a');
    const converged = await page
      .waitForFunction(() => window.__mobot.localization.converged === true, null, { timeout: 8000 })
      .then(() => true, () => false);
    let back = 'no estimator switch on this server';
    if (await served(t.base(), '/api/v1/localization/method')) {
      await page.selectOption('[data-testid=loc-method]', 'ekf');
      await until('/robot to report the EKF', async () => /^ekf/.test((await api('GET', '/api/v1/robot')).localization.method), 6000, 150);
      await page.waitForFunction(() => /EKF/.test(document.querySelector('[data-testid=loc-current]')?.textContent ?? ''), null, { timeout: 6000 });
      // The topic runs "while the particle filter runs": the cloud should go (the page drops one 2 s
      // old). Reported, not required: whether the filter stops is the server's business.
      const gone = await page
        .waitForFunction(() => window.__mobot.particles.drawn === 0, null, { timeout: 8000 })
        .then(() => true, () => false);
      back = `back to ekf; ${gone ? 'the cloud is gone' : 'particles still arrive 8 s after the switch'}`;
    }
    // Where the filter left the estimate is not where the robot is, maybe: start the EKF at the truth.
    const truth = await api('GET', '/api/v1/sim/truth');
    await api('POST', '/api/v1/localization/pose', truth.pose);
    return `${particles.count} of ${particles.total} particles drawn; converged ${converged ? 'within 8 s of driving' : 'not within 8 s'}; ${back}`;
  });

  await step('mapping: Start, drive by keyboard, the map grows from tiles; Stop & save refuses an empty name, saves with one; the map is active and listed', async () => {
    await skipUnlessServed(t.base(), '/api/v1/mapping');
    const original = (await api('GET', '/api/v1/maps')).find((m) => m.active);
    await page.click('[data-testid=tab-live]');
    await dismissToasts();
    await api('PUT', '/api/v1/sim/clock', { time_scale: 2 });
    let saved = null;
    try {
      await page.click('[data-testid=mapping-start]');
      await until('GET /mapping to say mapping', async () => (await api('GET', '/api/v1/mapping')).mapping === true, 6000, 150);
      await page.waitForFunction(() => window.__mobot.mapping.phase === 'mapping', null, { timeout: 6000 });
      await page.waitForSelector('[data-testid=mapping-overlay]', { state: 'visible', timeout: 5000 });
      const mode = await until('/robot to report mode mapping', async () => ((await api('GET', '/api/v1/robot')).mode === 'mapping' ? 'mapping' : null), 6000, 200).catch(() => null);

      // While mapping, global localization is not offered: the button disables once the status
      // reports the SLAM (the server would refuse it with mapping_active).
      await page.waitForSelector('[data-testid=loc-global]:disabled', { timeout: 6000 });
      const refusal = await api('POST', '/api/v1/localization/global').then(
        () => 'accepted',
        (error) => String(error.message),
      );
      if (!refusal.includes('409') || !refusal.includes('mapping_active')) {
        throw new Error(`global localization while mapping: ${refusal}`);
      }

      // Drive: turn in place, then forward; the tiles come in and grow.
      await page.locator('[data-testid=map-canvas]').hover();
      await page.keyboard.down('a');
      await sleep(1500);
      await page.keyboard.up('a');
      await page.waitForFunction(() => window.__mobot.tiles.drawn > 0 && Number(document.querySelector('[data-testid=map-canvas]')?.dataset.tiles) > 0, null, { timeout: 10_000 });
      const first = await page.evaluate(() => window.__mobot.tiles);
      await page.keyboard.down('w');
      await sleep(1500);
      await page.keyboard.up('w');
      await page.keyboard.down('d');
      await sleep(1200);
      await page.keyboard.up('d');
      await page.waitForFunction((n) => window.__mobot.tiles.knownCells > n, first.knownCells, { timeout: 8000 });
      const grown = await page.evaluate(() => window.__mobot.tiles);
      const status = await api('GET', '/api/v1/mapping');
      if (!(status.scans > 0)) throw new Error(`GET /mapping says ${JSON.stringify(status)}`);
      await page.waitForFunction(() => /scans \d+/.test(document.querySelector('[data-testid=mapping-status]')?.textContent ?? ''), null, { timeout: 6000 });
      await screenshot(page, 'mapping.png');

      // An empty name is refused here: nothing is sent, mapping goes on.
      await page.fill('[data-testid=mapping-name]', '  ');
      await page.click('[data-testid=mapping-save]');
      await page.waitForSelector('[data-testid=mapping-error]:has-text("Enter a name")', { state: 'visible', timeout: 5000 });
      if (!(await api('GET', '/api/v1/mapping')).mapping) throw new Error('Stop & save with an empty name stopped mapping');

      const name = `web-map-${Date.now() % 100000}`;
      await page.fill('[data-testid=mapping-name]', name);
      await page.click('[data-testid=mapping-save]');
      await page.waitForFunction(() => window.__mobot.mapping.phase === 'idle' && window.__mobot.mapping.saved !== null, null, { timeout: 10_000 });
      saved = await page.evaluate(() => window.__mobot.mapping.saved);
      if ((await api('GET', '/api/v1/mapping')).mapping) throw new Error('GET /mapping still says mapping after Stop & save');
      const stored = (await api('GET', '/api/v1/maps')).find((m) => m.id === saved.id);
      if (!stored || stored.name !== name || !stored.active) throw new Error(`map #${saved.id} is ${JSON.stringify(stored)}, expected "${name}" and active`);
      // The Live map shows it whole (the tiles gave way).
      await page.waitForFunction((id) => window.__mobot.mapId === id && window.__mobot.tiles.count === 0, saved.id, { timeout: 6000 });
      await page.click('[data-testid=tab-maps]');
      await page.waitForSelector(`[data-testid=map-item][data-map-id="${saved.id}"].active`, { timeout: 5000 });
      const cardText = (await page.textContent(`[data-testid=map-item][data-map-id="${saved.id}"]`)) ?? '';
      if (!cardText.includes(name)) throw new Error(`the card of map #${saved.id} reads "${cardText}"`);
      await screenshot(page, 'mapping-saved.png');
      return `mode ${mode ?? '(not reported as mapping)'}; ${first.count} -> ${grown.count} tiles, ${grown.knownCells} cells known; ${status.scans} scans, ${status.nodes} nodes, ${status.loop_closures} loop closures; saved "${name}" as #${saved.id}, active`;
    } finally {
      // Leave the server as the rest of the test expects it: not mapping, the original map active.
      await page.click('[data-testid=tab-live]').catch(() => {});
      await api('POST', '/api/v1/mapping', { action: 'stop' }).catch(() => {});
      if (original && saved) await api('POST', `/api/v1/maps/${original.id}/activate`).catch(() => {});
      await api('PUT', '/api/v1/sim/clock', { time_scale: 1 }).catch(() => {});
    }
  });
}

function zoneSummary(zone) {
  return `${zone.polygon.length} vertices${zone.name ? `, "${zone.name}"` : ''}`;
}
