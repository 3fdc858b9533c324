// The Live page: map canvas with robot, scan, sonar, IR, costmaps, particles and truth; status,
// events and teleop panels (the Link card is link_panel.ts).

import type { RobotStatus } from '../api';
import { costColor, cssColor } from '../costmap';
import type { Costmap } from '../costmap';
import type { LaserScan, MapGrid, Pose2D } from '../frames';
import type { SonarReading } from '../map/layers/sonar';
import { LAYER_SWITCHES } from '../map/layer';
import type { LayerSwitch } from '../map/layer';
import type { ParticleSet } from '../particles';
import { setParts, showMethod } from '../status_text';
import type { TileUpdate } from '../tiles';
import { DIFFERENTIAL, kinematicsLabel, robotBody, steeringText } from '../tricycle';
import type { RobotBody } from '../tricycle';
import { MapView } from '../map/mapview';
import { mountJoystick, TeleopController } from '../teleop';
import type { Command, SendResult, TeleopSource } from '../teleop';
import { headingSigma } from '../goals';
import { byId, clockTime, deg, detailText, fmt, h } from '../ui';

export interface PoseData {
  x: number;
  y: number;
  theta: number;
  v: number;
  w: number;
  cov?: number[];
  /** Tricycles: the front wheel's angle (rad, CCW); absent on differential robots. */
  steering_rad?: number;
}

export interface RobotEvent {
  t: number;
  kind: string;
  detail: unknown;
  received: Date;
}

const MAX_EVENTS = 200;
/** The particles topic runs at 5 Hz while the filter does: a cloud this old (ms) is the filter's last, and goes. */
const PARTICLES_STALE_MS = 2000;

/** Costs shown in the costmap legend, one per swatch (data-cost). */
const LEGEND_COSTS: Record<string, number> = { free: 0, inflated: 128, inscribed: 253, lethal: 254, unknown: 255 };

/** Toggles shown only when the hello advertises their topic. */
const TOPIC_TOGGLES: Record<string, LayerSwitch> = { ir: 'ir', particles: 'particles', costmap: 'costmap', local_costmap: 'localCostmap' };

/** A standard deviation in cm (mm below 1 cm would read as 0.0). */
function cm(metres: number): string {
  if (metres < 0.01) return `${fmt(metres * 1000, 1)} mm`;
  return `${fmt(metres * 100, metres < 0.1 ? 1 : 0)} cm`;
}

export class LivePage {
  readonly mapView: MapView;
  readonly teleop: TeleopController;
  /** Called when the particle cloud went stale and was dropped. */
  onParticlesStale: (() => void) | null = null;
  poseCount = 0;
  lastPose: PoseData | null = null;
  status: RobotStatus | null = null;
  truth: { pose: Pose2D; collisions: number } | null = null;
  /** What the map draws for the robot (from /robot's kinematics and geometry). */
  body: RobotBody = DIFFERENTIAL;
  /** Why teleop is refused here (somebody else holds the operator lock); null while it is not. */
  teleopLock: string | null = null;
  private events: RobotEvent[] = [];
  private eventsDirty = false;
  private poseDirty = false;
  private particlesAt = 0;

  constructor(sendTeleop: (command: Command) => SendResult) {
    this.mapView = new MapView(byId<HTMLCanvasElement>('map-canvas'));
    byId('view-fit').addEventListener('click', () => this.mapView.fit());
    byId('view-robot').addEventListener('click', () => this.mapView.centerOnRobot());
    byId('view-zoom-in').addEventListener('click', () => this.mapView.zoom(1.4));
    byId('view-zoom-out').addEventListener('click', () => this.mapView.zoom(1 / 1.4));
    byId('trail-clear').addEventListener('click', () => this.mapView.layers.trail.clear());
    for (const layer of LAYER_SWITCHES) {
      const box = byId<HTMLInputElement>(`layer-${layer}`);
      // The checkbox as the page has it decides (a browser may restore a state on reload).
      this.mapView.setLayerShown(layer, box.checked);
      box.addEventListener('change', () => {
        this.mapView.setLayerShown(layer, box.checked);
        this.showCostmapLegend();
      });
    }
    for (const swatch of document.querySelectorAll<HTMLElement>('[data-cost]')) {
      const cost = LEGEND_COSTS[swatch.dataset.cost ?? ''];
      if (cost === undefined) continue;
      // One source for the overlay and its legend: costmap.ts.
      swatch.style.background = swatch.classList.contains('sw-inflated')
        ? `linear-gradient(90deg, ${cssColor(costColor(1))}, ${cssColor(costColor(252))})`
        : cssColor(costColor(cost));
    }

    this.teleop = new TeleopController({
      send: sendTeleop,
      onChange: (command, source) => this.showTeleop(command, source),
      onInterrupt: () => this.showTeleopInterrupted(),
    });
    mountJoystick(byId('joystick'), byId('joystick-knob'), this.teleop);
    const speed = byId<HTMLInputElement>('speed');
    const showSpeed = () => {
      this.teleop.speed = Number(speed.value) / 100;
      byId('speed-value').textContent = `${speed.value} %`;
      const { v, w } = this.teleop.limits;
      byId('teleop-limits').textContent = `max ${fmt(v)} m/s · ${fmt(w)} rad/s`;
    };
    speed.addEventListener('input', showSpeed);
    showSpeed();

    // Text panels refresh at 10 Hz: the pose arrives at 50 Hz, the DOM need not.
    window.setInterval(() => this.refreshText(), 100);
    window.setInterval(() => this.dropStaleParticles(), 1000);
  }

  // ---- stream data ----

  onPose(data: PoseData): void {
    this.poseCount++;
    this.lastPose = data;
    this.poseDirty = true;
    // Whatever the estimator (EKF, particle filter, odometry): a pose without its own covariance
    // is drawn with the one /robot last reported.
    const cov = Array.isArray(data.cov) && data.cov.length === 9 ? data.cov : this.status?.localization?.cov;
    this.mapView.setPose(cov ? { ...data, cov } : data);
  }

  onScan(scan: LaserScan): void {
    this.mapView.layers.scan.set(scan);
  }

  onMap(map: MapGrid): void {
    this.mapView.setMap(map);
    byId('map-empty').hidden = true;
  }

  /** Changed tiles of the map being built (mapping). */
  onTiles(update: TileUpdate): void {
    this.mapView.setTiles(update);
    if (this.mapView.tiles.size > 0) byId('map-empty').hidden = true;
  }

  onSonar(data: { readings?: SonarReading[] }): void {
    if (Array.isArray(data.readings)) this.mapView.layers.sonar.set(data.readings);
  }

  /** The IR ring: the same reading shape as the sonar's. */
  onIr(data: { readings?: SonarReading[] }): void {
    if (Array.isArray(data.readings)) this.mapView.layers.ir.set(data.readings);
  }

  onCostmap(costmap: Costmap): void {
    const layer = costmap.which === 'local' ? this.mapView.layers.localCostmap : this.mapView.layers.costmap;
    layer.set(costmap);
    this.showCostmapLegend();
  }

  /** A particle cloud; null (or none for PARTICLES_STALE_MS) when the filter stopped. */
  onParticles(particles: ParticleSet | null): void {
    this.particlesAt = particles ? performance.now() : 0;
    this.mapView.layers.particles.set(particles);
  }

  /** Whether a particle cloud came recently (the filter runs). */
  get particlesLive(): boolean {
    return this.particlesAt > 0 && performance.now() - this.particlesAt < PARTICLES_STALE_MS;
  }

  /** The hello's topics: the toggles (and legend rows) of topics this server has are shown. */
  setTopicsAvailable(topics: readonly string[]): void {
    for (const [topic, layer] of Object.entries(TOPIC_TOGGLES)) {
      const available = topics.includes(topic);
      byId(`layer-${layer}-label`).hidden = !available;
      if (!available) {
        if (layer === 'ir') this.mapView.layers.ir.set([]);
        if (layer === 'particles') this.mapView.layers.particles.set(null);
        if (layer === 'costmap') this.mapView.layers.costmap.set(null);
        if (layer === 'localCostmap') this.mapView.layers.localCostmap.set(null);
      }
    }
    document.body.classList.toggle('has-ir', topics.includes('ir'));
    document.body.classList.toggle('has-particles', topics.includes('particles'));
    this.showCostmapLegend();
  }

  /** The costmap legend shows while a costmap is drawn. */
  private showCostmapLegend(): void {
    const shown = (layer: LayerSwitch, has: boolean) => has && byId<HTMLInputElement>(`layer-${layer}`).checked;
    const on = shown('costmap', this.mapView.layers.costmap.cells > 0) || shown('localCostmap', this.mapView.layers.localCostmap.cells > 0);
    document.body.classList.toggle('costmap', on);
  }

  onTruth(data: { pose: Pose2D; collisions: number }): void {
    this.truth = data;
    this.mapView.layers.truth.set(data.pose);
  }

  onStatus(status: RobotStatus): void {
    this.status = status;
    this.poseDirty = true;
    this.body = robotBody(status);
    this.mapView.setRobotBody(this.body);
    // The pose topic's steering (50 Hz) is fresher; the status's serves a stream without it.
    if (typeof status.steering_rad === 'number' && typeof this.lastPose?.steering_rad !== 'number') this.mapView.setSteering(status.steering_rad);
    document.body.classList.toggle('tricycle', this.body.kind === 'tricycle');
    this.refreshStatus();
  }

  /** The steering angle shown (rad): the latest pose's, else the status's; null on a differential robot. */
  get steering(): number | null {
    if (this.body.kind !== 'tricycle') return null;
    const fromPose = this.lastPose?.steering_rad;
    if (typeof fromPose === 'number') return fromPose;
    return typeof this.status?.steering_rad === 'number' ? this.status.steering_rad : null;
  }

  onEvent(data: { t: number; kind: string; detail: unknown }): void {
    this.events.unshift({ ...data, received: new Date() });
    if (this.events.length > MAX_EVENTS) this.events.length = MAX_EVENTS;
    this.eventsDirty = true;
  }

  /** The e-stop state from a POST /estop reply, before the next status frame. */
  setEstop(engaged: boolean): void {
    if (this.status) {
      this.status = { ...this.status, estop: engaged };
      this.refreshStatus();
    }
  }

  /** The server applied teleop command `seq`; `rttMs` from sending it to this echo. */
  onTeleopAck(v: number, w: number, seq: number | null, rttMs: number | null): void {
    const el = byId('teleop-ack');
    el.textContent = `ack${seq === null ? '' : ` #${seq}`}${rttMs === null ? '' : ` · ${fmt(rttMs, 0)} ms`}`;
    el.title = `applied ${fmt(v)} m/s · ${fmt(w)} rad/s (within the speed limits)${rttMs === null ? '' : `; sent -> applied -> echo in ${fmt(rttMs, 1)} ms`}`;
    el.classList.remove('warn');
  }

  /** The link went down while driving: the command was dropped; driving needs a new press. */
  private showTeleopInterrupted(): void {
    const el = byId('teleop-ack');
    el.textContent = 'link lost: command dropped — press again once reconnected';
    el.classList.add('warn');
  }

  /**
   * Somebody else holds the operator lock (`reason` says who) or nobody does (null): the teleop card
   * stays visible but dimmed, says why, and shows a drive input as refused.
   */
  setTeleopLock(reason: string | null): void {
    this.teleopLock = reason;
    const card = byId('teleop-panel');
    card.classList.toggle('locked', reason !== null);
    const note = byId('teleop-locked');
    note.hidden = reason === null;
    note.textContent = reason ?? '';
    byId('joystick').title = reason ?? 'Drag to drive';
  }

  setTruthAvailable(available: boolean): void {
    byId('layer-truth-label').hidden = !available;
    if (!available) this.mapView.layers.truth.set(null);
  }

  // ---- panels ----

  private showTeleop(command: Command | null, source: TeleopSource | null): void {
    const el = byId('teleop-cmd');
    // A command the operator lock keeps from being sent is shown as refused, not as driving.
    const refused = !!command && this.teleopLock !== null;
    el.textContent = command ? `${refused ? 'refused: ' : ''}${source} ${fmt(command.v)} m/s · ${fmt(command.w)} rad/s` : 'idle';
    el.classList.toggle('driving', !!command && !refused);
    el.classList.toggle('refused', refused);
  }

  private refreshText(): void {
    if (this.poseDirty) {
      this.poseDirty = false;
      const p = this.lastPose ?? this.status?.pose;
      if (p) setParts(byId('st-pose'), [`x ${fmt(p.x)}`, `y ${fmt(p.y)}`, `θ ${deg(p.theta)}`]);
      const v = this.lastPose ? { v: this.lastPose.v, w: this.lastPose.w } : this.status?.velocity;
      if (v) setParts(byId('st-vel'), [`v ${fmt(v.v)} m/s`, `w ${fmt(v.w)} rad/s`]);
      const cov = this.lastPose?.cov ?? this.status?.localization?.cov;
      if (Array.isArray(cov) && cov.length === 9) {
        const sx = Math.sqrt(Math.max(0, cov[0]!));
        const sy = Math.sqrt(Math.max(0, cov[4]!));
        const st = headingSigma(cov);
        setParts(byId('st-sigma'), [`x ${cm(sx)}`, `y ${cm(sy)}`, `θ ${st === null ? '–' : deg(st)}`]);
      }
      if (this.body.kind === 'tricycle') {
        const steering = byId('st-steering');
        steering.textContent = steeringText(this.steering);
        const g = this.body.geometry;
        steering.title = `${kinematicsLabel(this.body)}: front wheel angle (positive steers left); wheelbase ${fmt(g.wheelbase)} m${this.body.assumed ? ' (assumed: /robot has no geometry)' : ''}`;
      }
      if (this.truth) {
        const t = this.truth.pose;
        byId('st-truth').textContent = `x ${fmt(t.x)}  y ${fmt(t.y)}  θ ${deg(t.theta)}`;
        byId('st-collisions').textContent = String(this.truth.collisions);
      }
    }
    if (this.eventsDirty) {
      this.eventsDirty = false;
      this.renderEvents();
    }
  }

  private refreshStatus(): void {
    const s = this.status;
    if (!s) return;
    const mode = byId('st-mode');
    mode.textContent = s.mode;
    mode.dataset.mode = s.mode;
    showMethod(byId('st-loc'), s.localization?.method);
    const estop = byId('st-estop');
    estop.textContent = s.estop ? 'ENGAGED' : 'released';
    estop.className = s.estop ? 'bad' : 'good';
    const sensors = byId('st-sensors');
    sensors.replaceChildren(
      ...Object.entries(s.sensors ?? {})
        .sort(([a], [b]) => a.localeCompare(b))
        .map(([name, health]) =>
          h(
            'span',
            {
              class: `sensor ${health.ok ? 'ok' : 'fault'}`,
              title: `${name}: ${health.ok ? 'ok' : `FAULT (${health.reason ?? 'unknown'})`}, ${fmt(health.rate_hz, 1)} Hz`,
            },
            h('span', { class: 'dot' }),
            name,
            // A faulty device says why (a pulled cable reads "missing"), a good one how fast it runs.
            h('span', { class: 'rate', text: health.ok ? `${fmt(health.rate_hz, 0)} Hz` : (health.reason ?? 'fault') }),
          ),
        ),
    );
  }

  private renderEvents(): void {
    const list = byId('events');
    list.replaceChildren(
      ...this.events.slice(0, 60).map((e) =>
        h(
          'li',
          { class: `event kind-${e.kind.replace(/[^a-z0-9_-]/gi, '')}`, testid: 'event-item' },
          h('span', { class: 'time mono', title: `robot clock ${fmt(e.t, 3)} s`, text: clockTime(e.received) }),
          h('span', { class: 'kind', text: e.kind }),
          h('span', { class: 'detail', text: detailText(e.detail) }),
        ),
      ),
    );
    byId('events-count').textContent = this.events.length ? `${this.events.length}` : '';
  }

  /** Once a second: a particle cloud nobody refreshed is the stopped filter's last, and goes. */
  private dropStaleParticles(): void {
    if (this.particlesAt > 0 && !this.particlesLive) {
      this.onParticles(null);
      this.onParticlesStale?.();
    }
  }
}
