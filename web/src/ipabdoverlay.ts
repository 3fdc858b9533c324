// The "3D obstacles" layer of the Live map: the IPaBD obstacle map of the newest finished 3D sweep
// (GET /api/v1/sweeps/{id}/obstacle_map) drawn over the 2D map, so what the tilting laser found
// (beams, table tops) shows next to what the plain 2D laser sees. Fetched when switched on and
// again whenever a sweep finishes.

import { ApiError, errorText } from './apierror';
import type { ApiClient } from './api';
import { obstacleGridFromJson } from './ipabd';
import type { IpabdObstaclesLayer } from './map/layers/ipabd_obstacles';
import { newestSweep } from './sweeps';
import { toast } from './ui';

/** The server answers 409 sweep_not_done until IPaBD has run and the map is stored: ask again this often. */
const NOT_DONE_RETRY_MS = 500;
const NOT_DONE_RETRIES = 10;

export class IpabdOverlay {
  enabled = false;
  /** Sweep whose obstacle map is drawn, or null. */
  sweepId: number | null = null;
  lastError: string | null = null;
  /** Bumped per request so a slow older reply cannot replace a newer one. */
  private request = 0;

  constructor(
    private readonly api: ApiClient,
    private readonly layer: IpabdObstaclesLayer,
    private readonly status: HTMLElement,
  ) {}

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    if (enabled) void this.refresh();
    else {
      this.request++;
      this.sweepId = null;
      this.layer.set(null);
      this.showStatus('');
    }
  }

  /** A `sweep` event: a finished sweep brings a new obstacle map. */
  onSweepEvent(detail: unknown): void {
    const d = (detail ?? {}) as { id?: unknown; status?: unknown };
    if (this.enabled && d.status === 'done' && Number.isInteger(Number(d.id))) void this.refresh(Number(d.id));
  }

  /** Loads the obstacle map of sweep `id`, or of the newest finished sweep. */
  async refresh(id?: number): Promise<void> {
    const request = ++this.request;
    try {
      let sweepId = id;
      if (sweepId === undefined) {
        const newest = newestSweep(await this.api.sweeps(), (s) => s.status === 'done');
        if (request !== this.request) return;
        if (!newest) {
          this.showStatus('no finished 3D sweep yet');
          this.layer.set(null);
          return;
        }
        sweepId = newest.id;
      }
      this.showStatus(`loading sweep #${sweepId}…`);
      const json = await this.fetchWhenDone(sweepId, request);
      if (!json || request !== this.request) return;
      const grid = obstacleGridFromJson(json);
      this.sweepId = sweepId;
      this.lastError = null;
      this.layer.set(grid);
      this.showStatus(`sweep #${sweepId}: ${this.layer.cells} cells`);
    } catch (error) {
      if (request !== this.request) return;
      this.lastError = errorText(error);
      this.showStatus('not available');
      toast(`3D obstacles: ${this.lastError}`, 'error');
    }
  }

  private async fetchWhenDone(id: number, request: number) {
    for (let attempt = 0; ; attempt++) {
      try {
        return await this.api.sweepObstacleMap(id);
      } catch (error) {
        const notYet = error instanceof ApiError && error.code === 'sweep_not_done';
        if (!notYet || attempt >= NOT_DONE_RETRIES) throw error;
        await new Promise((resolve) => window.setTimeout(resolve, NOT_DONE_RETRY_MS));
        if (request !== this.request) return null;
      }
    }
  }

  private showStatus(text: string): void {
    this.status.textContent = text;
    this.status.title = text;
  }
}
