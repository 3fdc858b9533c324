// Goal navigation on the Live page: the "Set goal" tool (press for the position, drag for the
// heading), the goal panel (status, reason, replans, elapsed, remaining, cancel, recent goals),
// the path and goal marker on the map, and the simulator tools (drop obstacles, set the initial
// pose). Goals come from GET /api/v1/goals on connect and then from the `goal` and `path` topics.

import { ApiError, errorText } from './apierror';
import type { ApiClient } from './api';
import { ControllerChoice, DEFAULT_CONTROLLER } from './controllers';
import { distanceToTarget, goalElapsed, GoalStore, isFinished, parseGoal, parsePoints, pathLength, PLANNERS } from './goals';
import type { Goal } from './goals';
import { STATUS_COLORS } from './map/colors';
import type { MapTool } from './map/input';
import type { ObstacleMarker } from './map/layers/obstacles';
import type { MapView } from './map/mapview';
import { byId, deg, duration, fmt, h, toast } from './ui';

export type NavMode = 'goal' | 'obstacle' | 'pose';

/** The last refused request, for the panel and the test hooks. */
export interface NavError {
  status: number;
  code: string;
  message: string;
}

const OBSTACLE_RADIUS_M = 0.25;
const OBSTACLE_HEIGHT_M = 1.0;

const MODE_INFO: Record<NavMode, { buttons: string[]; color: string; text: string }> = {
  goal: {
    buttons: ['goal-mode'],
    color: '#34d399',
    text: 'Set goal · press for the position, drag for the heading',
  },
  obstacle: {
    buttons: ['sim-obstacle-mode'],
    color: '#fb923c',
    text: 'Drop obstacle · click where the 0.25 m post goes',
  },
  // Any backend: the Localization card has the button too (the Simulation card only with a simulator).
  pose: {
    buttons: ['sim-pose-mode', 'loc-set-pose'],
    color: '#c4b5fd',
    text: 'Set initial pose · press at the position, drag for the heading',
  },
};

/** Human text for the refusals of POST /goals (the server's message follows it). */
const ERROR_TEXT: Record<string, string> = {
  goal_in_obstacle: 'The goal is inside an obstacle or too close to one for the robot.',
  goal_outside_map: 'The goal is outside the map.',
  no_path: 'There is no collision-free path to the goal.',
  estop_engaged: 'The e-stop is engaged: release it first.',
  forbidden: 'This token may not do that (the operator role is needed).',
  no_map: 'There is no map to plan on.',
  unsupported_planner: 'That planner is not available in this server build.',
  unsupported_controller: 'That controller is not available on this robot.',
  goal_finished: 'The goal has already ended.',
};

export class NavigationPanel {
  readonly store = new GoalStore(30);
  /** Controllers offered: every contract name until the server refuses one. */
  readonly controllers = new ControllerChoice();
  mode: NavMode | null = null;
  lastError: NavError | null = null;
  /** Robot clock (s) of the latest frame. */
  clock: number | null = null;
  obstacles: ObstacleMarker[] = [];
  /** Whether keyboard shortcuts apply (the Live page is shown). */
  enabled = true;
  simAvailable = false;
  /** Why goals are refused here (somebody else holds the operator lock); null while they are not. */
  goalLock: string | null = null;
  /** Set goal was pressed while goals are refused: the operator card says why and asks again. */
  onLockedAttempt: (() => void) | null = null;
  private renderedVersion = -1;
  private pending = false;

  constructor(
    private readonly api: ApiClient,
    private readonly mapView: MapView,
    private readonly pose: () => { x: number; y: number; theta: number } | null,
  ) {
    const planner = byId<HTMLSelectElement>('goal-planner');
    planner.replaceChildren(
      ...PLANNERS.map((p) => h('option', { text: p.available ? p.label : `${p.label} (not in this build)`, attrs: { value: p.name, ...(p.available ? {} : { disabled: '' }) } })),
    );
    this.renderControllers();

    byId('goal-mode').addEventListener('click', () => this.toggleMode('goal'));
    byId('sim-obstacle-mode').addEventListener('click', () => this.toggleMode('obstacle'));
    byId('sim-pose-mode').addEventListener('click', () => this.toggleMode('pose'));
    byId('loc-set-pose').addEventListener('click', () => this.toggleMode('pose'));
    byId('map-mode-cancel').addEventListener('click', () => this.setMode(null));
    byId('goal-cancel').addEventListener('click', () => void this.cancel());
    window.addEventListener('keydown', (e) => this.onKey(e));
    window.setInterval(() => this.refresh(), 200);
    this.render();
  }

  // ---- stream and connection ----

  /** On (re)connect: the server's goal list replaces what we had. */
  async load(): Promise<void> {
    try {
      const goals = await this.api.goals();
      this.store.reset((Array.isArray(goals) ? goals : []).map(parseGoal).filter((g): g is Goal => g !== null));
      this.render();
    } catch (error) {
      // Informative only: the topics keep the panel current.
      console.warn('mobot: GET /api/v1/goals failed', error);
    }
  }

  onGoal(data: unknown): void {
    const goal = parseGoal(data);
    if (!goal) return;
    this.store.upsert(goal);
  }

  onPath(data: unknown): void {
    const message = data as { goal_id?: unknown; points?: unknown };
    if (typeof message?.goal_id !== 'number') return;
    this.store.setPath({ goal_id: message.goal_id, points: parsePoints(message.points) });
  }

  onClock(t: number): void {
    if (Number.isFinite(t)) this.clock = t;
  }

  /** The controller select: the names offered, a refused one disabled, the choice kept when still offered. */
  renderControllers(): void {
    const select = byId<HTMLSelectElement>('goal-controller');
    const chosen = this.controllers.pick(select.value || DEFAULT_CONTROLLER);
    select.replaceChildren(
      ...this.controllers.options().map((c) => h('option', { text: c.label, attrs: { value: c.name, ...(c.available ? {} : { disabled: '' }) } })),
    );
    select.value = chosen;
  }

  /** Another server process: its controllers are learnt anew. */
  serverChanged(): void {
    this.controllers.reset();
    this.renderControllers();
  }

  setSimAvailable(available: boolean): void {
    this.simAvailable = available;
    if (!available && this.mode === 'obstacle') this.setMode(null);
  }

  /** The server restarted or the simulator was reset: none of the obstacles we dropped is left. */
  clearObstacles(): void {
    this.obstacles = [];
    this.renderObstacles();
  }

  // ---- modes ----

  toggleMode(mode: NavMode): void {
    this.setMode(this.mode === mode ? null : mode);
  }

  /** Somebody else holds the operator lock (`reason` says who), or nobody does (null). */
  setGoalLock(reason: string | null): void {
    this.goalLock = reason;
    const button = byId('goal-mode');
    // Not `disabled`: a press still comes and is answered with why.
    button.setAttribute('aria-disabled', String(reason !== null));
    button.title = reason ?? 'Set goal (G): press on the map for the position, drag for the heading, release to send';
    const note = byId('goal-locked');
    note.hidden = reason === null;
    note.textContent = reason ?? '';
    if (reason !== null && this.mode === 'goal') this.setMode(null);
  }

  setMode(mode: NavMode | null): void {
    if (mode === 'obstacle' && !this.simAvailable) mode = null;
    if (mode === 'goal' && this.goalLock !== null) {
      this.onLockedAttempt?.();
      return;
    }
    this.mode = mode;
    for (const [name, info] of Object.entries(MODE_INFO)) {
      for (const id of info.buttons) {
        const button = byId(id);
        button.classList.toggle('active', name === mode);
        button.setAttribute('aria-pressed', String(name === mode));
      }
    }
    const banner = byId('map-mode');
    banner.hidden = !mode;
    if (mode) {
      const info = MODE_INFO[mode];
      byId('map-mode-text').textContent = info.text;
      byId('map-mode-dot').style.background = info.color;
      banner.dataset.mode = mode;
    }
    this.mapView.setTool(mode ? this.tool(mode) : null);
  }

  private tool(mode: NavMode): MapTool {
    const color = MODE_INFO[mode].color;
    switch (mode) {
      case 'goal':
        return { name: 'goal', color, heading: true, done: (p, theta) => void this.submitGoal(p.x, p.y, theta) };
      case 'obstacle':
        return { name: 'obstacle', color, heading: false, radius: OBSTACLE_RADIUS_M, done: (p) => void this.dropObstacle(p.x, p.y) };
      case 'pose':
        return { name: 'pose', color, heading: true, done: (p, theta) => void this.setPose(p.x, p.y, theta) };
    }
  }

  private onKey(e: KeyboardEvent): void {
    if (!this.enabled || e.ctrlKey || e.metaKey || e.altKey || e.repeat) return;
    const target = e.target as HTMLElement | null;
    if (target && (target.isContentEditable || /^(INPUT|TEXTAREA|SELECT)$/.test(target.tagName))) return;
    if (!byId('login').hidden) return;
    const key = e.key.toLowerCase();
    if (key === 'escape' && this.mode) {
      this.setMode(null);
      e.preventDefault();
    } else if (key === 'g') {
      this.toggleMode('goal');
      e.preventDefault();
    } else if (key === 'o' && this.simAvailable) {
      this.toggleMode('obstacle');
      e.preventDefault();
    } else if (key === 'p') {
      this.toggleMode('pose');
      e.preventDefault();
    }
  }

  // ---- requests ----

  async submitGoal(x: number, y: number, theta: number | null): Promise<void> {
    // One goal per gesture: the tool is left; press G again for the next one.
    this.setMode(null);
    const body: { x: number; y: number; theta?: number; planner: string; controller: string } = {
      x: round(x, 3),
      y: round(y, 3),
      planner: byId<HTMLSelectElement>('goal-planner').value || 'astar',
      controller: byId<HTMLSelectElement>('goal-controller').value || 'lyapunov',
    };
    if (theta !== null) body.theta = round(theta, 4);
    this.pending = true;
    this.showError(null);
    this.render();
    try {
      const reply = parseGoal(await this.api.submitGoal(body));
      // The panel and the marker show the new goal: no toast needed.
      if (reply) this.store.upsert(reply);
    } catch (error) {
      this.mapView.layers.errorMark.flash(x, y);
      if (error instanceof ApiError && error.code === 'unsupported_controller') {
        // This robot lacks it: offer it no more, and fall back to the default for the next goal.
        this.controllers.refuse(body.controller);
        this.renderControllers();
      }
      this.showError(error, 'Goal refused');
    } finally {
      this.pending = false;
      this.render();
    }
  }

  async cancel(): Promise<void> {
    const goal = this.store.current;
    if (!goal || isFinished(goal)) return;
    try {
      const reply = await this.api.cancelGoal(goal.id);
      const parsed = parseGoal(reply);
      if (parsed) this.store.upsert(parsed);
      else this.store.upsert({ ...goal, status: 'canceled' });
    } catch (error) {
      this.showError(error, 'Cancel failed');
    }
    this.render();
  }

  async dropObstacle(x: number, y: number): Promise<void> {
    try {
      const reply = await this.api.addObstacle({ x: round(x, 3), y: round(y, 3), radius: OBSTACLE_RADIUS_M, height: OBSTACLE_HEIGHT_M });
      this.obstacles = [...this.obstacles, { id: reply.id, x, y, radius: OBSTACLE_RADIUS_M }];
      this.renderObstacles();
      this.showError(null);
    } catch (error) {
      this.mapView.layers.errorMark.flash(x, y);
      this.showError(error, 'Obstacle refused');
    }
  }

  async removeObstacle(id: number): Promise<void> {
    try {
      await this.api.removeObstacle(id);
    } catch (error) {
      // 404: the simulator no longer has it (reset or restarted); drop it from the list anyway.
      if (!(error instanceof ApiError && error.status === 404)) {
        this.showError(error, 'Remove failed');
        return;
      }
    }
    this.obstacles = this.obstacles.filter((o) => o.id !== id);
    this.renderObstacles();
  }

  async setPose(x: number, y: number, theta: number | null): Promise<void> {
    this.setMode(null);
    const heading = theta ?? this.pose()?.theta ?? 0;
    try {
      await this.api.setLocalizationPose({ x: round(x, 3), y: round(y, 3), theta: round(heading, 4) });
      this.mapView.layers.trail.clear();
      this.showError(null);
      toast(`Localization re-initialised at x ${fmt(x)} y ${fmt(y)} θ ${deg(heading)}`, 'ok');
    } catch (error) {
      this.mapView.layers.errorMark.flash(x, y);
      this.showError(error, 'Set pose refused');
    }
  }

  private showError(error: unknown, what = 'Refused'): void {
    const box = byId('goal-error');
    if (!error) {
      this.lastError = null;
      box.hidden = true;
      box.replaceChildren();
      return;
    }
    const status = error instanceof ApiError ? error.status : 0;
    const code = error instanceof ApiError ? error.code : 'error';
    const message = error instanceof ApiError ? error.message : errorText(error);
    this.lastError = { status, code, message };
    box.hidden = false;
    box.dataset.code = code;
    const children: Node[] = [
      h('div', { class: 'goal-error-head' },
        h('strong', { text: what }),
        h('span', { class: 'code mono', testid: 'goal-error-code', text: `${status ? `${status} ` : ''}${code}` }),
        h('button', { class: 'close', title: 'Dismiss', text: '×', on: { click: () => this.showError(null) } }),
      ),
      // The server's own message first; ours when it sent none.
      h('div', { class: 'goal-error-text', text: message || ERROR_TEXT[code] || code }),
    ];
    box.replaceChildren(...children);
    toast(`${what}: ${message || ERROR_TEXT[code] || code} (${code})`, 'error');
  }

  // ---- rendering ----

  /** 5 Hz: elapsed time and distance change without frames of the goal topic. */
  private refresh(): void {
    if (this.store.version !== this.renderedVersion) this.render();
    else this.renderLive();
  }

  private render(): void {
    this.renderedVersion = this.store.version;
    const goal = this.store.current;
    this.mapView.layers.path.set(this.store.path, !goal || isFinished(goal));
    this.mapView.layers.goal.set(goal ? { x: goal.target.x, y: goal.target.y, theta: goal.target.theta, status: goal.status } : null);

    const status = byId('goal-status');
    status.textContent = goal ? goal.status : this.pending ? 'sending…' : 'no goal';
    status.dataset.status = goal ? goal.status : 'none';
    byId('goal-id').textContent = goal ? `#${goal.id}` : '';
    const cancel = byId<HTMLButtonElement>('goal-cancel');
    cancel.disabled = !goal || isFinished(goal);
    byId('goal-target').textContent = goal
      ? `x ${fmt(goal.target.x)}  y ${fmt(goal.target.y)}  ${goal.target.theta !== undefined ? `θ ${deg(goal.target.theta)}` : 'θ any'}`
      : '–';
    byId('goal-replans').textContent = goal ? String(goal.replans ?? 0) : '–';
    const reason = byId('goal-reason');
    reason.textContent = goal?.reason ?? '–';
    reason.className = goal?.status === 'failed' ? 'bad' : '';
    const points = this.store.path.length;
    byId('goal-path').textContent = points > 1 ? `${points} points · ${fmt(pathLength(this.store.path), 1)} m` : '–';
    byId('goal-algo').textContent = goal ? `${goal.planner ?? '?'} · ${goal.controller ?? '?'}` : '–';
    this.renderLive();
    this.renderHistory();
  }

  private renderLive(): void {
    const goal = this.store.current;
    const elapsed = goal ? goalElapsed(goal, this.clock) : null;
    byId('goal-elapsed').textContent = elapsed === null ? '–' : elapsed < 60 ? `${fmt(elapsed, 1)} s` : duration(elapsed);
    const remaining = goal ? distanceToTarget(goal, this.pose()) : null;
    byId('goal-remaining').textContent = remaining === null ? '–' : `${fmt(remaining)} m`;
  }

  private renderHistory(): void {
    const list = byId('goal-history');
    const goals = this.store.recent(6);
    if (goals.length === 0) {
      list.replaceChildren(h('li', { class: 'empty small', text: 'No goals yet: press G and click the map.' }));
      return;
    }
    list.replaceChildren(
      ...goals.map((g) => {
        const elapsed = goalElapsed(g, this.clock);
        return h(
          'li',
          { class: `goal-item${g.id === this.store.current?.id ? ' current' : ''}`, testid: 'goal-history-item', attrs: { 'data-status': g.status, 'data-id': String(g.id) } },
          h('span', { class: 'mono muted', text: `#${g.id}` }),
          h('span', { class: 'status-dot', attrs: { style: `background:${STATUS_COLORS[g.status] ?? '#94a3b8'}` } }),
          h('span', { class: 'status-text', text: g.status }),
          h('span', { class: 'mono target', text: `${fmt(g.target.x, 1)}, ${fmt(g.target.y, 1)}` }),
          h('span', { class: 'mono muted', text: elapsed === null ? '' : `${fmt(elapsed, 0)} s` }),
          h('span', { class: 'reason muted', title: g.reason ?? '', text: g.reason ?? '' }),
        );
      }),
    );
  }

  renderObstacles(): void {
    this.mapView.layers.obstacles.set(this.obstacles);
    const list = byId('sim-obstacles');
    if (this.obstacles.length === 0) {
      list.replaceChildren(h('li', { class: 'empty small', text: 'No obstacles dropped.' }));
      return;
    }
    list.replaceChildren(
      ...this.obstacles.map((o) =>
        h(
          'li',
          { class: 'obstacle-item', testid: 'sim-obstacle-item', attrs: { 'data-id': String(o.id) } },
          h('span', { class: 'sw sw-obstacle' }),
          h('span', { class: 'mono', text: `#${o.id}` }),
          h('span', { class: 'mono muted', text: `x ${fmt(o.x)}  y ${fmt(o.y)}  r ${fmt(o.radius)}` }),
          h('button', {
            class: 'btn small ghost',
            testid: 'sim-obstacle-remove',
            title: `Remove obstacle #${o.id} (DELETE /api/v1/sim/obstacles/${o.id})`,
            text: 'Remove',
            on: { click: () => void this.removeObstacle(o.id) },
          }),
        ),
      ),
    );
  }
}

function round(x: number, digits: number): number {
  const k = 10 ** digits;
  return Math.round(x * k) / k;
}
