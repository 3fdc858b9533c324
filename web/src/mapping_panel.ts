// The Mapping card of the Live page: Start mapping, the live status (scans, nodes, loop closures,
// elapsed, tiles received), Stop & save under a name (an empty one is refused here, nothing is
// sent) and Discard; the MAPPING badge over the map. The state logic is mapping.ts; this renders it
// and talks to POST/GET /api/v1/mapping. GET /mapping is asked on connect, once a second while
// mapping, on every `mapping` event and when the robot's mode disagrees with the panel.

import { ApiError } from './apierror';
import type { ApiClient, RobotStatus } from './api';
import { MappingState, parseMappingStatus } from './mapping';
import type { MappingRequest } from './mapping';
import type { TileStore } from './tile_store';
import { byId, duration, fmt, toast } from './ui';

const POLL_MS = 1000;
const RENDER_MS = 500;

export interface MappingPanelHooks {
  /** Robot clock (s) of the latest frame. */
  clock(): number | null;
  /** The tiles of the map being built, as the map view holds them. */
  tiles(): TileStore;
  /** Mapping ended: `saved` is the stored (and now active) map, null when discarded or stopped elsewhere. */
  ended(saved: { id: number; name: string } | null): void;
}

export class MappingPanel {
  readonly state = new MappingState();
  private renderedVersion = -1;
  private pollTimer: number | undefined;
  private refreshing: Promise<void> | null = null;
  private readonly nameInput: HTMLInputElement;

  constructor(
    private readonly api: ApiClient,
    private readonly hooks: MappingPanelHooks,
  ) {
    this.nameInput = byId<HTMLInputElement>('mapping-name');
    byId('mapping-start').addEventListener('click', () => void this.request('start'));
    byId('mapping-save-form').addEventListener('submit', (e) => {
      e.preventDefault();
      void this.request('save');
    });
    byId('mapping-discard').addEventListener('click', () => {
      if (window.confirm('Discard the map being built? It is not stored.')) void this.request('discard');
    });
    this.nameInput.addEventListener('input', () => {
      this.nameInput.removeAttribute('aria-invalid');
      if (this.state.error && !this.state.busy) this.state.showError(null);
    });
    window.setInterval(() => this.render(), RENDER_MS);
    this.render();
  }

  /** On (re)connect: the server's mapping state (404: this server cannot map). */
  async connected(): Promise<void> {
    await this.refresh();
  }

  /** The robot's status (1 Hz): a mode that disagrees with the panel asks GET /mapping. */
  onStatus(status: RobotStatus): void {
    if (this.state.modeDisagrees(status.mode)) void this.refresh();
  }

  /** A `mapping` event (started, stopped, saved, from any client). */
  onEvent(): void {
    void this.refresh();
  }

  async refresh(): Promise<void> {
    this.refreshing ??= (async () => {
      const wasMapping = this.state.mapping;
      try {
        const status = parseMappingStatus(await this.api.mapping());
        if (status) this.state.onStatus(status);
      } catch (error) {
        if (error instanceof ApiError && error.status === 404 && error.code === 'not_found') this.state.onUnsupported();
        // Otherwise (unreachable, 5xx): keep what we know; the next poll asks again.
      } finally {
        this.refreshing = null;
      }
      // Stopped elsewhere (another client, a reset): the tiles go, the whole map comes back.
      if (wasMapping && this.state.phase === 'idle') this.hooks.ended(null);
      this.schedulePoll();
      this.render();
    })();
    return this.refreshing;
  }

  async request(request: MappingRequest): Promise<void> {
    const name = this.nameInput.value;
    const refusal = this.state.refusal(request, name);
    if (refusal) {
      // Refused here: nothing is sent (an empty name, a request under way).
      this.state.showError(refusal);
      if (request === 'save') {
        this.nameInput.setAttribute('aria-invalid', 'true');
        this.nameInput.focus();
      }
      this.render();
      return;
    }
    this.state.begin(request);
    this.render();
    try {
      const reply =
        request === 'start' ? await this.api.startMapping() : await this.api.stopMapping(request === 'save' ? name.trim() : undefined);
      this.state.succeeded(request, reply ?? {}, name);
      if (request === 'start') {
        toast('Mapping started: drive the robot to grow the map', 'ok');
      } else if (request === 'save') {
        const saved = this.state.saved;
        toast(saved ? `Map "${saved.name}" saved as #${saved.id} and made active` : 'Mapping stopped and saved', 'ok');
        this.nameInput.value = '';
        this.hooks.ended(saved);
      } else {
        toast('Mapping stopped; the map was discarded', 'info');
        this.hooks.ended(null);
      }
    } catch (error) {
      this.state.failed(request, error);
      if (this.state.error) toast(this.state.error, 'error');
      // mapping_active / not_mapping: the server knows better; ask it.
      void this.refresh();
    }
    this.schedulePoll();
    this.render();
  }

  private schedulePoll(): void {
    window.clearTimeout(this.pollTimer);
    this.pollTimer = undefined;
    if (!this.state.mapping) return;
    this.pollTimer = window.setTimeout(() => void this.refresh(), POLL_MS);
  }

  private render(): void {
    const s = this.state;
    const controls = s.controls();
    byId<HTMLButtonElement>('mapping-start').disabled = !controls.start;
    byId<HTMLButtonElement>('mapping-save').disabled = !controls.save;
    byId<HTMLButtonElement>('mapping-discard').disabled = !controls.discard;
    this.nameInput.disabled = !controls.name;
    const phase = byId('mapping-phase');
    phase.dataset.status = s.phase;
    phase.textContent = { unknown: '–', unsupported: 'not on this server', idle: 'idle', starting: 'starting…', mapping: 'mapping', saving: 'saving…', discarding: 'discarding…' }[s.phase];
    byId('mapping-live').hidden = !s.mapping;
    const overlay = byId('mapping-overlay');
    overlay.hidden = !s.mapping;
    document.body.classList.toggle('mapping', s.mapping);
    const tiles = this.hooks.tiles();
    if (s.mapping) {
      const summary = s.summary() ?? '–';
      byId('mapping-status').textContent = summary;
      const elapsed = s.elapsed(this.hooks.clock());
      byId('mapping-elapsed').textContent = elapsed === null ? '–' : elapsed < 60 ? `${fmt(elapsed, 0)} s` : duration(elapsed);
      byId('mapping-tiles').textContent = tiles.size ? `${tiles.size} tiles · ${tiles.knownCells().toLocaleString()} cells known` : 'none yet';
      byId('mapping-overlay-text').textContent = s.status ? `${s.status.scans} scans · ${s.status.nodes} nodes · ${s.status.loop_closures} loops` : '';
    }
    const note = byId('mapping-note');
    const saved = s.saved;
    note.hidden = !(saved || s.phase === 'unsupported');
    note.className = `panel-note small${saved ? ' good' : ''}`;
    note.textContent = s.phase === 'unsupported' ? 'This server cannot build maps (no /api/v1/mapping).' : saved ? `Saved as "${saved.name}" (#${saved.id}), the active map.` : '';
    if (s.version === this.renderedVersion) return;
    this.renderedVersion = s.version;
    const box = byId('mapping-error');
    box.hidden = !s.error;
    box.textContent = s.error ?? '';
  }
}
