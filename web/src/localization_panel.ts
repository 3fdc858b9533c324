// The Localization card of the Live page: the estimator switch (PUT /api/v1/localization/method),
// "Localize globally" (POST /api/v1/localization/global: the particle filter spreads over the map),
// the method and converged flag as /robot reports them, the size of the particle cloud, and the
// refusals (no_map, mapping_active, a server without these endpoints).

import type { ApiClient, PathPresence, RobotStatus } from './api';
import { estimatorOf, ESTIMATORS, localizationErrorText, methodLabel, parseLocalization } from './localization';
import type { EstimatorName, LocalizationStatus } from './localization';
import type { ParticleSet } from './particles';
import { methodDetail } from './status_text';
import { byId, h, toast } from './ui';

export class LocalizationPanel {
  /** The latest /robot localization. */
  status: LocalizationStatus = { method: null, cov: null, converged: null };
  lastError: string | null = null;
  /** A global localization was started from this page and has not converged yet. */
  globalRunning = false;
  particles: { count: number; total: number } | null = null;
  /** The estimator was switched from this page (PUT accepted). */
  onEstimatorChanged: ((method: EstimatorName) => void) | null = null;
  private readonly presence = { global: 'unknown' as PathPresence, method: 'unknown' as PathPresence };
  private pending = false;
  private readonly select: HTMLSelectElement;
  private readonly globalButton: HTMLButtonElement;

  constructor(private readonly api: ApiClient) {
    this.select = byId<HTMLSelectElement>('loc-method');
    this.select.replaceChildren(...ESTIMATORS.map((e) => h('option', { text: e.label, attrs: { value: e.name } })));
    this.select.value = 'ekf';
    this.select.addEventListener('change', () => void this.setMethod(this.select.value as EstimatorName));
    this.globalButton = byId<HTMLButtonElement>('loc-global');
    this.globalButton.addEventListener('click', () => void this.localizeGlobally());
    this.render();
  }

  /** On (re)connect: which of the two endpoints this server has (GET: 405 present, 404 absent). */
  async connected(): Promise<void> {
    const [global, method] = await Promise.all([this.api.probe('/api/v1/localization/global'), this.api.probe('/api/v1/localization/method')]);
    this.presence.global = global;
    this.presence.method = method;
    this.render();
  }

  onStatus(robot: RobotStatus): void {
    const previous = this.status.converged;
    this.status = parseLocalization(robot.localization);
    if (this.globalRunning && this.status.converged === true && previous !== true) {
      this.globalRunning = false;
      toast('Global localization converged', 'ok');
    }
    this.render();
  }

  onParticles(set: ParticleSet | null): void {
    this.particles = set ? { count: set.count, total: set.total } : null;
    this.renderParticles();
  }

  async localizeGlobally(): Promise<void> {
    this.pending = true;
    this.showError(null);
    this.render();
    try {
      const reply = await this.api.localizeGlobally();
      this.globalRunning = true;
      toast(`Global localization started (${reply?.method ?? 'particle_filter'})`, 'ok');
    } catch (error) {
      this.showError(localizationErrorText(error, 'global'));
    } finally {
      this.pending = false;
      this.render();
    }
  }

  async setMethod(method: EstimatorName): Promise<void> {
    const current = estimatorOf(this.status.method);
    if (method === current) return;
    this.pending = true;
    this.showError(null);
    this.render();
    try {
      const reply = await this.api.setLocalizationMethod(method);
      this.globalRunning = false;
      toast(`Localization: ${reply?.method ?? method}`, 'ok');
      // The next status frame (1 Hz) brings the method; until then show what was asked.
      this.status = { ...this.status, method: parseLocalization({ method: reply?.method ?? method }).method };
      this.onEstimatorChanged?.(method);
    } catch (error) {
      this.showError(localizationErrorText(error, 'method'));
    } finally {
      this.pending = false;
      this.render();
    }
  }

  private showError(message: string | null): void {
    this.lastError = message;
    const box = byId('loc-error');
    box.hidden = !message;
    box.textContent = message ?? '';
    if (message) toast(message, 'error');
  }

  private render(): void {
    const method = this.status.method;
    const current = byId('loc-current');
    current.replaceChildren(...(method ? [methodLabel(method), ...(method.detail ? [' ', methodDetail(method.detail)] : [])] : ['–']));
    current.title = method?.raw ?? '';
    const slam = method?.family === 'slam';
    const estimator = estimatorOf(method);
    // The select follows the robot, unless the user is choosing or a request is out.
    if (!this.pending && document.activeElement !== this.select && estimator) this.select.value = estimator;
    this.select.disabled = this.pending || slam || this.presence.method === 'absent';
    this.select.title =
      this.presence.method === 'absent'
        ? 'This server cannot switch the estimator'
        : slam
          ? 'Mapping: SLAM localizes the robot until mapping stops'
          : 'Estimator (PUT /api/v1/localization/method)';
    this.globalButton.disabled = this.pending || slam || this.presence.global === 'absent';
    this.globalButton.title =
      this.presence.global === 'absent'
        ? 'This server has no global localization'
        : 'Global localization: spread particles over the map and let the filter find the robot (POST /api/v1/localization/global)';
    const converged = byId('loc-converged');
    const c = this.status.converged;
    converged.dataset.converged = c === null ? '' : String(c);
    converged.textContent = c === null ? '–' : c ? 'yes' : this.globalRunning ? 'not yet · localizing globally' : 'no';
    byId('loc-hint').textContent = this.presence.global === 'absent' && this.presence.method === 'absent' ? 'not on this server' : '';
    this.renderParticles();
  }

  private renderParticles(): void {
    const p = this.particles;
    byId('loc-particles').textContent = p ? `${p.count.toLocaleString()} drawn of ${p.total.toLocaleString()}` : '–';
  }
}
