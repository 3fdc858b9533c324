// The Runs page: recorded runs, the selected run's trajectory over the active map, its events and
// a CSV download of the trajectory.

import { errorText } from '../apierror';
import type { ApiClient, RunEvent, RunInfo, TrajectoryPoint } from '../api';
import type { MapGrid } from '../frames';
import { MapView } from '../map/mapview';
import { dateTime, detailText, duration, fmt, h, saveBlob, toast } from '../ui';

export class RunsPage {
  private readonly list: HTMLElement;
  private readonly error: HTMLElement;
  private readonly detail: HTMLElement;
  private readonly summary: HTMLElement;
  private readonly events: HTMLElement;
  private readonly csvButton: HTMLButtonElement;
  readonly mapView: MapView;
  private runs: RunInfo[] = [];
  private selected: number | null = null;
  private loading = false;
  trajectoryPoints = 0;

  constructor(
    root: HTMLElement,
    private readonly api: ApiClient,
  ) {
    this.list = h('ol', { class: 'run-list', testid: 'runs-list' });
    this.error = h('div', { class: 'page-error', testid: 'runs-error' });
    this.error.hidden = true;
    this.summary = h('div', { class: 'run-summary', testid: 'run-summary', text: 'Select a run.' });
    this.events = h('ol', { class: 'events', testid: 'run-events' });
    this.csvButton = h('button', { class: 'btn small', testid: 'run-csv', text: 'Download CSV', on: { click: () => void this.downloadCsv() } });
    this.csvButton.disabled = true;
    const canvas = h('canvas', { testid: 'run-canvas' });
    this.detail = h(
      'div',
      { class: 'run-detail' },
      h('div', { class: 'run-head' }, this.summary, h('div', { class: 'spacer' }), this.csvButton),
      h(
        'div',
        { class: 'run-body' },
        h('div', { class: 'map-panel run-map' }, canvas, h('div', { class: 'map-toolbar' }, h('button', { class: 'btn small', text: 'Fit', on: { click: () => this.mapView.fit() } }))),
        h('div', { class: 'card run-events-card' }, h('h2', { text: 'Events' }), this.events),
      ),
    );
    root.append(
      h(
        'div',
        { class: 'page-head' },
        h('h1', { text: 'Runs' }),
        h('div', { class: 'spacer' }),
        h('button', { class: 'btn', testid: 'runs-refresh', text: 'Refresh', on: { click: () => void this.refresh() } }),
      ),
      this.error,
      h('div', { class: 'runs-layout' }, h('div', { class: 'card run-list-card' }, this.list), this.detail),
    );
    this.mapView = new MapView(canvas, { showRobot: false });
  }

  setMap(map: MapGrid): void {
    this.mapView.setMap(map);
  }

  async refresh(): Promise<void> {
    if (this.loading) return;
    this.loading = true;
    try {
      this.runs = await this.api.runs();
      this.error.hidden = true;
      this.renderList();
      if (this.selected === null && this.runs.length > 0) {
        const newest = [...this.runs].sort((a, b) => b.started - a.started)[0]!;
        void this.select(newest.id);
      } else if (this.selected !== null) {
        void this.select(this.selected);
      }
    } catch (error) {
      this.error.textContent = `Could not list the runs: ${errorText(error)}`;
      this.error.hidden = false;
    } finally {
      this.loading = false;
    }
  }

  private renderList(): void {
    if (this.runs.length === 0) {
      this.list.replaceChildren(h('li', { class: 'empty', text: 'No runs recorded.' }));
      return;
    }
    const sorted = [...this.runs].sort((a, b) => b.started - a.started);
    this.list.replaceChildren(
      ...sorted.map((run) => {
        const ongoing = run.ended === undefined;
        const length = (ongoing ? Date.now() / 1000 : run.ended!) - run.started;
        const item = h(
          'li',
          { class: `run-item${run.id === this.selected ? ' selected' : ''}`, testid: 'run-item', attrs: { 'data-run-id': String(run.id), tabindex: '0' } },
          h('div', { class: 'run-title' }, h('strong', { text: run.name || `run ${run.id}` }), ongoing ? h('span', { class: 'badge live', text: 'recording' }) : null),
          h('div', { class: 'muted small', text: `${dateTime(run.started)} · ${duration(length)}` }),
          h(
            'div',
            { class: 'muted small', text: `${fmt(run.distance_m, 1)} m · goals ${run.goals.succeeded}✓ ${run.goals.failed}✗ ${run.goals.canceled}⊘` },
          ),
        );
        item.addEventListener('click', () => void this.select(run.id));
        item.addEventListener('keydown', (e) => {
          if (e.key === 'Enter') void this.select(run.id);
        });
        return item;
      }),
    );
  }

  private async select(id: number): Promise<void> {
    const changed = this.selected !== id;
    this.selected = id;
    for (const el of this.list.querySelectorAll<HTMLElement>('.run-item')) {
      el.classList.toggle('selected', el.dataset.runId === String(id));
    }
    const run = this.runs.find((r) => r.id === id);
    this.csvButton.disabled = false;
    let trajectory: TrajectoryPoint[] = [];
    let events: RunEvent[] = [];
    try {
      [trajectory, events] = await Promise.all([this.api.trajectory(id), this.api.runEvents(id)]);
    } catch (error) {
      this.summary.textContent = `Could not load run #${id}: ${errorText(error)}`;
      return;
    }
    if (this.selected !== id) return;
    this.trajectoryPoints = trajectory.length;
    this.mapView.layers.trajectory.set(trajectory);
    // A run on a map is shown on the whole map; without one the view follows the trajectory.
    if (changed && !this.mapView.getMap()) this.mapView.fitPoints(trajectory);
    const first = trajectory[0];
    const last = trajectory[trajectory.length - 1];
    this.summary.replaceChildren(
      h('strong', { text: run?.name || `run ${id}` }),
      h(
        'span',
        {
          class: 'muted',
          text: ` · ${trajectory.length} poses${first && last ? ` over ${duration(last.t - first.t)}` : ''} · ${fmt(run?.distance_m, 1)} m · ${events.length} events`,
        },
      ),
    );
    this.events.replaceChildren(
      ...(events.length
        ? [...events]
            .sort((a, b) => b.t - a.t)
            .slice(0, 300)
            .map((e) =>
              h(
                'li',
                { class: `event kind-${e.kind.replace(/[^a-z0-9_-]/gi, '')}` },
                h('span', { class: 'time mono', text: `${fmt(e.t, 1)} s` }),
                h('span', { class: 'kind', text: e.kind }),
                h('span', { class: 'detail', text: detailText(e.detail) }),
              ),
            )
        : [h('li', { class: 'empty', text: 'No events.' })]),
    );
  }

  private async downloadCsv(): Promise<void> {
    if (this.selected === null) return;
    try {
      saveBlob(await this.api.blob(`/api/v1/runs/${this.selected}/trajectory?format=csv`), `run-${this.selected}.csv`);
    } catch (error) {
      toast(`Download failed: ${errorText(error)}`, 'error');
    }
  }
}
