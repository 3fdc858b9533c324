// The 3D page: start a tilting-laser sweep (mode selector), its progress (cloud chunks, with a
// GET /sweeps/{id} poll once a second as the fallback), refusals, the sweeps list, the PLY download
// and the 3D view. The view (three.js) is imported on first show, so the Live page does not load
// it; chunks are collected in the tracker whether or not the view exists.

import { ApiError, errorText } from '../apierror';
import type { ApiClient } from '../api';
import { heightLegendGradient } from '../cloud';
import type { CloudView } from '../cloudview';
import { decodeBinaryFrame } from '../frames';
import type { CloudChunk, MapGrid, Pose2D } from '../frames';
import { newestSweep, SWEEP_PERIODS_S, SWEEP_STEPS_DEG, sweepErrorText, SweepTracker } from '../sweeps';
import type { SweepChange, SweepInfo, SweepRequest } from '../sweeps';
import { fmt, h, saveBlob, toast } from '../ui';

const POLL_INTERVAL_MS = 1000;
const PANEL_REFRESH_MS = 100;
/** Progress values kept for the test hook (distinct values seen by the progress bar). */
const MAX_PROGRESS_SEEN = 64;

export class CloudPage {
  readonly tracker = new SweepTracker();
  /** Distinct progress values the bar showed for the tracked sweep, in order. */
  progressSeen: number[] = [];
  lastError: string | null = null;
  view: CloudView | null = null;
  viewError: string | null = null;

  private sweeps: SweepInfo[] = [];
  private active = false;
  private viewLoading: Promise<void> | null = null;
  private initialLoaded = false;
  private pollTimer: number | undefined;
  private dirty = true;
  private pose: Pose2D | null = null;
  private map: MapGrid | null = null;
  private fullCloudLoading: number | null = null;
  /** Sweep whose whole-cloud load failed: not retried on every change (choosing it again does). */
  private fullCloudFailed: number | null = null;

  private readonly periodSelect: HTMLSelectElement;
  private readonly stepSelect: HTMLSelectElement;
  private readonly startButton: HTMLButtonElement;
  private readonly errorBox: HTMLElement;
  private readonly progressBar: HTMLElement;
  private readonly progressFill: HTMLElement;
  private readonly progressLabel: HTMLElement;
  private readonly statusText: HTMLElement;
  private readonly panel: HTMLElement;
  private readonly emptyNote: HTMLElement;
  private readonly legend: HTMLElement;
  private readonly legendHigh: HTMLElement;
  private readonly legendLow: HTMLElement;
  private readonly legendPoints: HTMLElement;
  private readonly sweepSelect: HTMLSelectElement;
  private readonly details: HTMLElement;
  private readonly plyButton: HTMLButtonElement;

  constructor(
    root: HTMLElement,
    private readonly api: ApiClient,
  ) {
    this.periodSelect = h(
      'select',
      { testid: 'sweep-period', title: 'Tilt period: one sweep of the laser from its lowest to its highest pitch' },
      ...SWEEP_PERIODS_S.map((p) => h('option', { text: `${p} s`, attrs: { value: String(p) } })),
    );
    this.stepSelect = h(
      'select',
      { testid: 'sweep-step', title: 'Angular step of the laser within a scan' },
      ...SWEEP_STEPS_DEG.map((d) => h('option', { text: `${d}°`, attrs: { value: String(d) } })),
    );
    this.startButton = h('button', {
      class: 'btn primary',
      testid: 'sweep-start',
      text: '3D sweep',
      title: 'Start a 3D sweep of the tilting laser (POST /api/v1/sweeps); the robot should stand still meanwhile',
      on: { click: () => void this.start() },
    });
    this.errorBox = h('div', { class: 'page-error', testid: 'sweep-error', attrs: { role: 'alert' } });
    this.errorBox.hidden = true;
    this.progressFill = h('div', { class: 'fill' });
    this.progressLabel = h('span', { class: 'label mono', text: 'no sweep' });
    this.progressBar = h(
      'div',
      { class: 'sweep-progress', testid: 'sweep-progress', attrs: { role: 'progressbar', 'aria-valuemin': '0', 'aria-valuemax': '100', 'aria-valuenow': '0', 'data-progress': '0' } },
      this.progressFill,
      this.progressLabel,
    );
    this.statusText = h('span', { class: 'badge status', testid: 'sweep-status', attrs: { 'data-status': 'none' }, text: 'no sweep' });

    this.emptyNote = h('div', { class: 'map-empty', testid: 'cloud-empty', text: 'No 3D sweep yet: press “3D sweep”.' });
    this.legendHigh = h('span', { class: 'mono' });
    this.legendLow = h('span', { class: 'mono' });
    this.legendPoints = h('div', { class: 'mono small', testid: 'cloud-points' });
    this.legend = h(
      'div',
      { class: 'cloud-legend', testid: 'cloud-legend', title: 'Colour by height (z, map frame)' },
      h('div', { class: 'small muted', text: 'height z' }),
      h(
        'div',
        { class: 'legend-scale' },
        h('div', { class: 'legend-bar', attrs: { style: `background: ${heightLegendGradient()}` } }),
        h('div', { class: 'legend-labels' }, this.legendHigh, this.legendLow),
      ),
      this.legendPoints,
    );
    this.legend.hidden = true;
    this.panel = h(
      'div',
      { class: 'map-panel cloud-panel', testid: 'cloud-view', attrs: { 'data-points': '0' } },
      h(
        'div',
        { class: 'map-toolbar' },
        h('button', { class: 'btn small', testid: 'cloud-reset-view', text: 'Reset view', title: 'Show the whole sweep and map', on: { click: () => this.view?.resetView() } }),
        h('span', { class: 'hint', text: 'drag: orbit · right drag: pan · wheel: zoom' }),
      ),
      this.legend,
      this.emptyNote,
    );

    this.sweepSelect = h('select', { testid: 'sweep-select', title: 'The sweep shown' });
    this.sweepSelect.addEventListener('change', () => void this.choose(Number(this.sweepSelect.value)));
    this.details = h('dl', { class: 'kv', testid: 'sweep-details' });
    this.plyButton = h('button', {
      class: 'btn small',
      testid: 'sweep-ply',
      text: 'Download PLY',
      title: 'The cloud in the map frame (GET /api/v1/sweeps/{id}/cloud?format=ply)',
      on: { click: () => void this.downloadPly() },
    });
    this.plyButton.disabled = true;

    root.append(
      h(
        'div',
        { class: 'page-head' },
        h('h1', { text: '3D' }),
        h('span', { class: 'muted small', text: 'tilting-laser sweeps · IPaBD' }),
        h('div', { class: 'spacer' }),
        h('label', { class: 'field inline' }, h('span', { text: 'period' }), this.periodSelect),
        h('label', { class: 'field inline' }, h('span', { text: 'step' }), this.stepSelect),
        this.startButton,
      ),
      this.errorBox,
      h('div', { class: 'sweep-bar' }, this.statusText, this.progressBar),
      h(
        'div',
        { class: 'cloud-layout' },
        this.panel,
        h(
          'aside',
          { class: 'card cloud-side' },
          h('h2', { text: 'Sweep' }),
          this.sweepSelect,
          this.details,
          h('div', { class: 'actions' }, this.plyButton),
        ),
      ),
    );
    window.setInterval(() => this.refreshPanel(), PANEL_REFRESH_MS);
  }

  // ---- page lifecycle ----

  /** The page is shown: load the view (first time) and the sweeps. */
  async show(): Promise<void> {
    this.active = true;
    this.view?.setActive(true);
    void this.loadView();
    const listed = await this.refreshList();
    if (listed && !this.initialLoaded) await this.loadInitial();
  }

  hide(): void {
    this.active = false;
    this.view?.setActive(false);
  }

  /** The stream (re)connected: pick up a sweep that runs (started elsewhere, or while we were away). */
  async connected(): Promise<void> {
    if (!(await this.refreshList())) return;
    const running = newestSweep(this.sweeps, (s) => s.status === 'running');
    if (running) this.apply(this.tracker.show(running));
    else if (this.tracker.id !== null && this.tracker.status === 'running') {
      // It ended while we were disconnected.
      const info = this.sweeps.find((s) => s.id === this.tracker.id);
      if (info) this.apply(this.tracker.onInfo(info));
    }
    if (this.active && !this.initialLoaded) await this.loadInitial();
    this.ensurePolling();
  }

  // ---- stream data ----

  onChunk(chunk: CloudChunk): void {
    this.apply(this.tracker.onChunk(chunk));
    this.ensurePolling();
  }

  onSweepEvent(detail: unknown): void {
    if (!detail || typeof detail !== 'object') return;
    const d = detail as { id?: unknown; status?: unknown };
    this.apply(this.tracker.onEvent(d));
    // The event's detail is partial: ask for the whole record (status, points, reason).
    if (Number(d.id) === this.tracker.id) void this.pollOnce();
    void this.refreshList();
    this.ensurePolling();
  }

  onPose(pose: Pose2D): void {
    this.pose = pose;
    this.view?.setPose(pose);
  }

  onMap(map: MapGrid): void {
    this.map = map;
    this.view?.setMap(map);
  }

  // ---- actions ----

  private mode(): SweepRequest {
    return {
      period_s: Number(this.periodSelect.value) as SweepRequest['period_s'],
      step_deg: Number(this.stepSelect.value) as SweepRequest['step_deg'],
    };
  }

  async start(): Promise<void> {
    this.startButton.disabled = true;
    try {
      const info = await this.api.startSweep(this.mode());
      this.clearError();
      this.apply(this.tracker.follow(info.id));
      this.apply(this.tracker.onInfo(info));
      toast(`3D sweep #${info.id} started`, 'ok');
      void this.refreshList();
    } catch (error) {
      this.showError(sweepErrorText(error));
      // Another sweep runs: follow it, so its progress is what the bar shows.
      if (error instanceof ApiError && error.code === 'sweep_running') void this.connected();
    } finally {
      this.ensurePolling();
      this.dirty = true;
    }
  }

  /** Shows a listed sweep (the selector). */
  private async choose(id: number): Promise<void> {
    const info = this.sweeps.find((s) => s.id === id);
    if (!info || id === this.tracker.id) return;
    this.fullCloudFailed = null;
    this.apply(this.tracker.show(info)); // a done sweep: apply() loads its cloud
    this.ensurePolling();
  }

  private async downloadPly(): Promise<void> {
    const id = this.tracker.id;
    if (id === null) return;
    try {
      saveBlob(await this.api.blob(`/api/v1/sweeps/${id}/cloud?format=ply`), `sweep-${id}.ply`);
    } catch (error) {
      toast(`Download failed: ${errorText(error)}`, 'error');
    }
  }

  // ---- loading ----

  private async loadView(): Promise<void> {
    if (this.view || this.viewError) return;
    this.viewLoading ??= (async () => {
      try {
        const { CloudView } = await import('../cloudview');
        const view = new CloudView(this.panel, this.tracker.cloud);
        if (this.map) view.setMap(this.map);
        if (this.pose) view.setPose(this.pose);
        view.sync();
        view.setActive(this.active);
        this.view = view;
      } catch (error) {
        this.viewError = `The 3D view cannot start: ${errorText(error)} (WebGL is needed).`;
        this.lastError = this.viewError;
      } finally {
        this.dirty = true;
      }
    })();
    await this.viewLoading;
  }

  /** GET /sweeps; false when it failed. */
  private async refreshList(): Promise<boolean> {
    try {
      this.sweeps = await this.api.sweeps();
    } catch (error) {
      // A server without sweeps (404) or one that is down: the page says so when it is shown.
      if (this.active) this.showError(`Could not list the sweeps: ${errorText(error)}`);
      return false;
    }
    const current = this.sweeps.find((s) => s.id === this.tracker.id);
    if (current) this.apply(this.tracker.onInfo(current));
    this.renderList();
    return true;
  }

  /** On first show (once listed): the running sweep if one runs, else the newest finished one with its cloud. */
  private async loadInitial(): Promise<void> {
    this.initialLoaded = true;
    if (this.tracker.id !== null) return; // a sweep arrived on the stream already
    const running = newestSweep(this.sweeps, (s) => s.status === 'running');
    const done = newestSweep(this.sweeps, (s) => s.status === 'done');
    const chosen = running ?? done;
    if (!chosen) return;
    this.apply(this.tracker.show(chosen)); // a done sweep: apply() loads its cloud
    this.ensurePolling();
  }

  /** Replaces the tracked sweep's points with the server's whole cloud (one binary frame). */
  private async loadFullCloud(id: number): Promise<void> {
    if (this.fullCloudLoading === id) return;
    this.fullCloudLoading = id;
    try {
      const frame = decodeBinaryFrame(await this.api.sweepCloudFrame(id));
      if (frame.kind !== 'cloud') throw new Error(`the server sent a ${frame.header.topic} frame, not a cloud`);
      if (this.tracker.loadFull(frame.cloud)) this.view?.sync();
    } catch (error) {
      this.fullCloudFailed = id;
      if (this.tracker.id === id) this.showError(`Could not load the cloud of sweep #${id}: ${errorText(error)}`);
    } finally {
      this.fullCloudLoading = null;
      this.dirty = true;
    }
  }

  // ---- progress polling ----

  /** Polls GET /sweeps/{id} once a second while the tracked sweep runs. */
  private ensurePolling(): void {
    if (this.tracker.status !== 'running' || this.tracker.id === null) {
      window.clearTimeout(this.pollTimer);
      this.pollTimer = undefined;
      return;
    }
    if (this.pollTimer !== undefined) return;
    this.pollTimer = window.setTimeout(() => {
      this.pollTimer = undefined;
      void this.pollOnce().finally(() => this.ensurePolling());
    }, POLL_INTERVAL_MS);
  }

  private async pollOnce(): Promise<void> {
    const id = this.tracker.id;
    if (id === null) return;
    try {
      this.apply(this.tracker.onInfo(await this.api.sweep(id)));
    } catch {
      // The stream and the next poll keep trying.
    }
  }

  /** Acts on what a chunk, poll, event or reply did to the tracked sweep. */
  private apply(change: SweepChange): void {
    if (change.reset) {
      this.progressSeen = [];
      this.clearError();
      this.renderList();
    }
    if (change.finished) this.onFinished();
    // Done with points missing (dropped chunks, joined midway, or a listed sweep): fetch it whole.
    const id = this.tracker.id;
    if (this.tracker.needsFullCloud && id !== null && this.fullCloudFailed !== id) void this.loadFullCloud(id);
    this.view?.sync();
    this.dirty = true;
  }

  private onFinished(): void {
    const t = this.tracker;
    if (t.status === 'failed') {
      this.showError(`3D sweep #${t.id} failed${t.info?.reason ? `: ${t.info.reason}` : ''}.`);
    } else if (t.status === 'done') {
      // The last poll may predate the end: the points held (or about to be reloaded) are the count.
      toast(`3D sweep #${t.id} done: ${Math.max(t.cloud.count, t.info?.points ?? 0)} points`, 'ok');
    }
    void this.refreshList();
  }

  // ---- rendering ----

  private showError(message: string): void {
    this.lastError = message;
    this.errorBox.textContent = message;
    this.errorBox.hidden = false;
    toast(message, 'error');
  }

  private clearError(): void {
    this.errorBox.hidden = true;
  }

  private renderList(): void {
    const sorted = [...this.sweeps].sort((a, b) => b.id - a.id);
    const id = this.tracker.id;
    if (id !== null && !sorted.some((s) => s.id === id)) {
      sorted.unshift({ id, status: this.tracker.status ?? 'running', points: 0, mode: { period_s: 0, step_deg: 0, scans: 0 }, scans_done: 0, started_t: 0 });
    }
    this.sweepSelect.replaceChildren(
      ...(sorted.length
        ? sorted.map((s) => h('option', { text: `#${s.id} · ${s.status}${s.points ? ` · ${s.points} pts` : ''}`, attrs: { value: String(s.id) } }))
        : [h('option', { text: 'no sweeps', attrs: { value: '' } })]),
    );
    if (id !== null) this.sweepSelect.value = String(id);
    this.sweepSelect.disabled = sorted.length === 0;
  }

  private refreshPanel(): void {
    if (!this.dirty) {
      // The view's count changes at its own pace; the legend follows it.
      if (this.view && this.legendPoints.dataset.drawn !== String(this.view.drawnPoints)) this.dirty = true;
      else return;
    }
    this.dirty = false;
    const t = this.tracker;
    const progress = t.progress;
    // Floored: "100 %" only once the bar is full (0.996 rounded read 100 over a part-filled bar).
    const percent = progress >= 1 ? 100 : Math.floor(progress * 100);
    this.progressFill.style.width = `${(progress * 100).toFixed(1)}%`;
    this.progressBar.dataset.progress = progress.toFixed(4);
    this.progressBar.setAttribute('aria-valuenow', String(percent));
    const scans = t.scansTotal > 0 ? `scan ${Math.min(t.scansDone, t.scansTotal)} / ${t.scansTotal}` : '';
    const stage = t.status === 'running' && t.scanned ? ' · processing (IPaBD)' : '';
    this.progressLabel.textContent = t.id === null ? 'no sweep' : `${percent} %${scans ? ` · ${scans}` : ''}${stage}`;
    if (t.id !== null && this.progressSeen[this.progressSeen.length - 1] !== progress && this.progressSeen.length < MAX_PROGRESS_SEEN) {
      this.progressSeen.push(progress);
    }
    const status = t.status ?? 'none';
    this.statusText.dataset.status = status;
    this.statusText.textContent = t.id === null ? 'no sweep' : `#${t.id} ${status}`;
    this.startButton.disabled = t.status === 'running';
    this.startButton.title = t.status === 'running' ? `3D sweep #${t.id} is running` : 'Start a 3D sweep of the tilting laser (POST /api/v1/sweeps)';

    const count = t.cloud.count;
    this.panel.classList.toggle('has-points', count > 0);
    this.emptyNote.hidden = count > 0 && !this.viewError;
    this.emptyNote.textContent = this.viewError
      ? `${this.viewError} ${count} points received.`
      : t.id === null
        ? 'No 3D sweep yet: press “3D sweep”.'
        : t.status === 'running'
          ? 'Waiting for the first scan…'
          : t.status === 'failed'
            ? `Sweep #${t.id} failed.`
            : 'Loading the cloud…';
    const range = t.cloud.colorRange;
    this.legend.hidden = !range;
    if (range) {
      this.legendHigh.textContent = `${fmt(range.highM)} m`;
      this.legendLow.textContent = `${fmt(range.lowM)} m`;
    }
    const drawn = this.view?.drawnPoints ?? 0;
    this.legendPoints.dataset.drawn = String(drawn);
    this.legendPoints.textContent = `${count.toLocaleString()} points`;

    const info = t.info;
    const row = (label: string, value: string, testid?: string) => [h('dt', { text: label }), h('dd', { class: 'mono', text: value, testid })];
    this.details.replaceChildren(
      ...(t.id === null
        ? row('sweep', '–')
        : [
            ...row('status', status, 'sweep-detail-status'),
            ...row('mode', info ? `${info.mode.period_s} s · ${info.mode.step_deg}°` : '–'),
            ...row('scans', t.scansTotal ? `${Math.min(t.scansDone, t.scansTotal)} / ${t.scansTotal}` : '–'),
            ...row('points', `${count.toLocaleString()}${info && info.points > count ? ` of ${info.points.toLocaleString()}` : ''}`, 'sweep-detail-points'),
            ...row('z range', Number.isFinite(t.cloud.bounds.minZ) ? `${fmt(t.cloud.bounds.minZ)} … ${fmt(t.cloud.bounds.maxZ)} m` : '–'),
            ...row('started', info ? `${fmt(info.started_t, 1)} s` : '–'),
            ...row('took', info?.ended_t !== undefined ? `${fmt(info.ended_t - info.started_t, 1)} s` : '–'),
            ...(info?.reason ? row('reason', info.reason) : []),
          ]),
    );
    this.plyButton.disabled = t.status !== 'done';
  }
}
