// Dashboard entry: token, REST client, stream, pages, e-stop and the test hooks (window.__mobot).

import './style.css';
import { ApiClient } from './api';
import type { RobotStatus } from './api';
import { ApiError, errorText } from './apierror';
import { basePath, forgetToken, initialToken, saveToken, streamUrl } from './auth';
import { CameraPanel } from './camera_panel';
import { ClientsPanel } from './clients_panel';
import type { Pose2D } from './frames';
import type { SonarReading } from './map/layers/sonar';
import { LivePage } from './pages/live';
import type { PoseData } from './pages/live';
import { covarianceEllipse, headingSigma } from './goals';
import { NavigationPanel } from './nav';
import type { NavError, NavMode } from './nav';
import { IpabdOverlay } from './ipabdoverlay';
import { LocalizationPanel } from './localization_panel';
import { MappingPanel } from './mapping_panel';
import { isDrivingCommand } from './operator';
import { OperatorPanel } from './operator_panel';
import { ZonesPanel } from './zones_panel';
import { CloudPage } from './pages/cloud3d';
import { MapsPage } from './pages/maps';
import { RunsPage } from './pages/runs';
import { StreamClient } from './stream';
import type { ConnectionState } from './stream';
import { TTL_MS } from './teleop';
import { byId, toast } from './ui';

declare global {
  interface Window {
    __mobot: MobotHooks;
  }
}

/** Counters for the browser test; read-only views of the app state. */
export interface MobotHooks {
  readonly scansDrawn: number;
  readonly framesDrawn: number;
  readonly poseCount: number;
  readonly lastPose: Pose2D | null;
  readonly connected: boolean;
  readonly connection: ConnectionState;
  readonly mapShown: boolean;
  readonly robotVisible: boolean;
  readonly estop: boolean | null;
  readonly page: string;
  readonly lastError: string | null;
  readonly reconnects: number;
  /** The newest goal (REST list, POST reply or `goal` topic). */
  readonly lastGoal: { id: number; status: string; reason: string | null; replans: number } | null;
  /** Points of the path drawn on the map. */
  readonly pathPoints: number;
  /** Goals the panel knows. */
  readonly goalCount: number;
  /** The last refused navigation request (goal, obstacle, pose), or null. */
  readonly goalError: NavError | null;
  /** The active map tool. */
  readonly mapMode: NavMode | null;
  /** Obstacles dropped from this page. */
  readonly obstacles: { id: number; x: number; y: number; radius: number }[];
  /** The drawn EKF uncertainty: 2-sigma ellipse semi-axes (m), its angle and sigma(theta) (rad). */
  readonly uncertainty: { major: number; minor: number; angle: number; sigmaTheta: number | null } | null;
  /** The map view transform: screen = origin + scale * (x, -y), CSS pixels relative to the canvas. */
  readonly view: { scale: number; originX: number; originY: number };
  /** Map frame -> viewport (client) CSS pixels, for mouse events. */
  mapToClient(x: number, y: number): [number, number];
  /** The 3D page's sweep: progress 0..1, points held and drawn by the 3D view, progress values the bar showed. */
  readonly sweep: {
    id: number | null;
    status: string | null;
    progress: number;
    scansDone: number;
    scansTotal: number;
    points: number;
    drawnPoints: number;
    progressSeen: number[];
    error: string | null;
    viewReady: boolean;
  };
  /** Occupied IPaBD cells drawn over the Live map ("3D obstacles"), 0 when off. */
  readonly ipabdCells: number;
  /** Id of the whole map shown (0: not a stored map), null before one arrived. */
  readonly mapId: number | null;
  /** The map being built while mapping: tiles held, tiles drawn in the last frame, cells known. */
  readonly tiles: { count: number; drawn: number; knownCells: number };
  /** The mapping panel: phase (unknown|unsupported|idle|starting|mapping|saving|discarding), the server's counts, the last refusal, the map saved. */
  readonly mapping: { phase: string; mapping: boolean; scans: number; nodes: number; loopClosures: number; error: string | null; saved: { id: number; name: string } | null };
  /** Localization as /robot reports it, and the panel's last refusal. */
  readonly localization: { method: string | null; family: string | null; converged: boolean | null; error: string | null; globalRunning: boolean };
  /** The particle cloud: particles in the sample, in the filter, drawn in the last frame, samples drawn. */
  readonly particles: { count: number; total: number; drawn: number; setsDrawn: number };
  /** Cells of the global and local costmaps drawn (0: none). */
  readonly costmaps: { global: number; local: number };
  /** IR readings drawn. */
  readonly irReadings: number;
  /** Keep-out zones of the map shown, the draw mode's draft and the last refusal. */
  readonly zones: { mapId: number | null; count: number; drawn: number; drawing: boolean; vertices: number; problem: string | null; error: string | null };
  /** The robot's drawing: kinematics from /robot, the steering angle shown (tricycles; null otherwise). */
  readonly robot: { kinematics: string | null; body: string; steering: number | null };
  /**
   * The Camera card: shown (GET /camera answered 200), its kind, the camera topic subscribed, frames
   * drawn / decoded / dropped while decoding, the image size, the tracked target (status, box), the
   * last box sent, a box being drawn, whether the robot follows, the head's pan/tilt, the last refusal.
   */
  readonly camera: {
    available: boolean;
    kind: string | null;
    subscribed: boolean;
    quality: number;
    lastFrameBytes: number;
    framesDrawn: number;
    framesDecoded: number;
    framesDropped: number;
    width: number;
    height: number;
    target: { status: string; box: { x: number; y: number; w: number; h: number } | null; range: number | null };
    lastBox: { x: number; y: number; w: number; h: number } | null;
    drawing: boolean;
    following: boolean;
    head: { pan: number; tilt: number } | null;
    error: string | null;
  };
  /** Camera image pixels -> viewport (client) CSS pixels, for mouse events on the camera image. */
  cameraToClient(x: number, y: number): [number, number];
  /**
   * The Operator card: the server has the lock (null: not asked yet), the state (free, mine, other,
   * held: somebody whom the page cannot tell from itself, unknown, unsupported), the holder, this
   * page's token id once learnt, whether the token is an admin, the line and buttons shown, whether
   * teleop and goals are refused here, who took the lock from this page, the last refusal, the GETs.
   */
  readonly operator: {
    supported: boolean | null;
    state: string;
    holder: { tokenId: number; label: string | null; role: string | null; address: string | null; since: number | null } | null;
    me: number | null;
    admin: boolean | null;
    line: string;
    buttons: { acquire: boolean; release: boolean; takeOver: boolean };
    blocksCommands: boolean;
    lostTo: string | null;
    error: string | null;
    polls: number;
  };
  /** The Connected card (admins): shown, open, refreshing, the rows, GETs while open, the last error. */
  readonly clients: {
    shown: boolean;
    open: boolean;
    polling: boolean;
    polls: number;
    rows: { id: number; kind: string; label: string | null; role: string | null; address: string; topics: string[]; bytesSent: number; dropped: number }[];
    error: string | null;
  };
}

let token = initialToken();
const api = new ApiClient(token, basePath());
let estopEngaged: boolean | null = null;
let currentPage = 'live';
let lastError: string | null = null;
let connectionState: ConnectionState = 'disconnected';
let serverStartedAt: number | null = null;

const stream = new StreamClient({
  url: () => streamUrl(token),
  authProbe: async () => {
    try {
      await api.robot();
      return 'ok';
    } catch (error) {
      if (error instanceof ApiError && error.status === 401) return 'unauthorized';
      return 'unreachable';
    }
  },
  handlers: {
    state: (state, detail) => showConnection(state, detail),
    hello: (hello) => {
      const truth = (hello.topics ?? []).some((t) => t.name === 'truth');
      camera.onHello((hello.topics ?? []).map((t) => t.name));
      live.setTruthAvailable(truth);
      live.setTopicsAvailable((hello.topics ?? []).map((t) => t.name));
      nav.setSimAvailable(truth);
      document.body.classList.toggle('sim', truth);
      live.mapView.layers.trail.clear(); // the server may have restarted with the robot elsewhere
    },
    json: (topic, data, meta) => {
      switch (topic) {
        case 'pose':
          live.onPose(data as PoseData);
          cloud3d.onPose(data as PoseData);
          nav.onClock(meta.t);
          break;
        case 'goal':
          nav.onGoal(data);
          break;
        case 'path':
          nav.onPath(data);
          break;
        case 'status':
          onRobotStatus(data as RobotStatus);
          break;
        case 'target':
          camera.onTarget(data);
          break;
        case 'sonar':
          live.onSonar(data as { readings?: SonarReading[] });
          break;
        case 'ir':
          live.onIr(data as { readings?: SonarReading[] });
          break;
        case 'truth':
          live.onTruth(data as { pose: Pose2D; collisions: number });
          break;
        case 'events':
          live.onEvent(data as { t: number; kind: string; detail: unknown });
          // A simulator reset removes every dropped obstacle.
          if ((data as { kind?: string }).kind === 'sim_reset') nav.clearObstacles();
          if ((data as { kind?: string }).kind === 'sweep') {
            const detail = (data as { detail?: unknown }).detail;
            cloud3d.onSweepEvent(detail);
            ipabd.onSweepEvent(detail);
          }
          if ((data as { kind?: string }).kind === 'mapping') mapping.onEvent();
          if ((data as { kind?: string }).kind === 'ir_safety') showIrSafety((data as { detail?: unknown }).detail);
          if ((data as { kind?: string }).kind === 'fault') showFault((data as { detail?: unknown }).detail);
          if ((data as { kind?: string }).kind === 'follow') camera.onFollowEvent((data as { detail?: unknown }).detail);
          break;
        default:
          break;
      }
    },
    scan: (scan) => live.onScan(scan),
    map: (map) => {
      live.onMap(map);
      runs.setMap(map);
      cloud3d.onMap(map);
      zones.onMap(map);
    },
    tiles: (update) => live.onTiles(update),
    costmap: (costmap) => live.onCostmap(costmap),
    particles: (particles) => {
      live.onParticles(particles);
      localization.onParticles(particles);
    },
    cloud: (chunk) => cloud3d.onChunk(chunk),
    camera: (jpeg) => camera.onFrame(jpeg),
    serverError: (code, message) => {
      lastError = `${code}: ${message}`;
      if (code === 'operator_busy') {
        // Teleop is the only stream op the lock guards; the card asks who drives now.
        toast(`Teleop refused: ${message}`, 'error');
        operator.commandRefused();
        return;
      }
      toast(`${message} (${code})`, 'error');
    },
    teleopAck: (v, w) => {
      live.onTeleopAck(v, w);
      operator.commandAccepted();
    },
  },
});

const live = new LivePage(stream, (command) => {
  // Somebody else surely drives: nothing is sent (a held key would be refused 15 times a second);
  // a drive input says why, the release of one says nothing.
  if (operator.view.blocksCommands) {
    if (command.v !== 0 || command.w !== 0) lastError = operator.refuseLocally('Teleop') ?? lastError;
    return false;
  }
  const sent = stream.send({ op: 'teleop', v: command.v, w: command.w, ttl_ms: TTL_MS });
  if (!sent && (command.v !== 0 || command.w !== 0)) toast('Not connected: teleop is not sent', 'error');
  return sent;
});
const nav = new NavigationPanel(api, live.mapView, () => live.lastPose);
const camera = new CameraPanel(api, {
  send: (message) => stream.send(message),
  connected: () => stream.connected,
  refreshStatus: () => void api.robot().then(onRobotStatus, () => {}),
});
nav.renderObstacles();
const operator = new OperatorPanel(api, {
  changed: (view) => {
    const reason = view.blocksCommands ? view.lockedReason : null;
    live.setTeleopLock(reason);
    nav.setGoalLock(reason);
  },
});
nav.onLockedAttempt = () => {
  lastError = operator.refuseLocally('Goal') ?? lastError;
};
const clients = new ClientsPanel(api, { admin: (admin) => operator.setAdmin(admin) });
// Driving commands tell the card who this page is (accepted) or that somebody else drives (409).
api.onResponse = (method, path, error) => {
  if (error?.code === 'operator_busy') operator.commandRefused();
  else if (!error && isDrivingCommand(method, path)) operator.commandAccepted();
};
const maps = new MapsPage(byId('page-maps'), api);
const runs = new RunsPage(byId('page-runs'), api);
const cloud3d = new CloudPage(byId('page-3d'), api);
const ipabd = new IpabdOverlay(api, live.mapView.layers.ipabd, byId('layer-ipabd-status'));
const localization = new LocalizationPanel(api);
const mapping = new MappingPanel(api, {
  clock: () => nav.clock,
  tiles: () => live.mapView.tiles,
  ended: (saved) => {
    if (!saved) {
      live.mapView.clearTiles();
      return;
    }
    // The saved map is now the active one: the Maps page lists it so, and the `map` topic sends it
    // whole (which replaces the tiles); should it not come, the tiles go anyway.
    void maps.refresh();
    window.setTimeout(() => {
      if (!mapping.state.mapping) live.mapView.clearTiles();
    }, 3000);
  },
});
live.onParticlesStale = () => localization.onParticles(null);
/** The particle filter is not the estimator (any more): its last cloud goes now, not when it is stale. */
function dropParticles(): void {
  if (!live.mapView.layers.particles.current) return;
  live.onParticles(null);
  localization.onParticles(null);
}
localization.onEstimatorChanged = (method) => {
  if (method !== 'particle_filter') dropParticles();
};
const zones = new ZonesPanel(api, live.mapView, { leaveOtherTools: () => nav.setMode(null) });
byId<HTMLInputElement>('layer-ipabd').addEventListener('change', (e) => {
  const on = (e.target as HTMLInputElement).checked;
  document.body.classList.toggle('ipabd', on);
  ipabd.setEnabled(on);
});

window.__mobot = {
  get scansDrawn() {
    return live.mapView.layers.scan.scansDrawn;
  },
  get framesDrawn() {
    return live.mapView.framesDrawn;
  },
  get poseCount() {
    return live.poseCount;
  },
  get lastPose() {
    const p = live.lastPose;
    return p ? { x: p.x, y: p.y, theta: p.theta } : null;
  },
  get connected() {
    return stream.connected;
  },
  get connection() {
    return connectionState;
  },
  get mapShown() {
    return live.mapView.mapShown;
  },
  get robotVisible() {
    return live.mapView.robotVisible();
  },
  get estop() {
    return estopEngaged;
  },
  get page() {
    return currentPage;
  },
  get lastError() {
    return lastError;
  },
  get reconnects() {
    return stream.reconnects;
  },
  get lastGoal() {
    const g = nav.store.current;
    return g ? { id: g.id, status: g.status, reason: g.reason ?? null, replans: g.replans ?? 0 } : null;
  },
  get pathPoints() {
    return live.mapView.layers.path.points;
  },
  get goalCount() {
    return nav.store.size;
  },
  get goalError() {
    return nav.lastError;
  },
  get mapMode() {
    return nav.mode;
  },
  get obstacles() {
    return nav.obstacles.map((o) => ({ ...o }));
  },
  get uncertainty() {
    const cov = live.lastPose?.cov;
    const e = covarianceEllipse(cov, 2);
    return e ? { major: e.major, minor: e.minor, angle: e.angle, sigmaTheta: headingSigma(cov) } : null;
  },
  get view() {
    const v = live.mapView.view;
    return { scale: v.scale, originX: v.originX, originY: v.originY };
  },
  mapToClient(x: number, y: number) {
    return live.mapView.mapToClient(x, y);
  },
  get sweep() {
    const t = cloud3d.tracker;
    return {
      id: t.id,
      status: t.status,
      progress: t.progress,
      scansDone: t.scansDone,
      scansTotal: t.scansTotal,
      points: t.cloud.count,
      drawnPoints: cloud3d.view?.drawnPoints ?? 0,
      progressSeen: [...cloud3d.progressSeen],
      error: cloud3d.lastError,
      viewReady: cloud3d.view !== null,
    };
  },
  get ipabdCells() {
    return live.mapView.layers.ipabd.cells;
  },
  get mapId() {
    return live.mapView.getMap()?.id ?? null;
  },
  get tiles() {
    const store = live.mapView.tiles;
    return { count: store.size, drawn: live.mapView.layers.mapTiles.tilesDrawn, knownCells: store.knownCells() };
  },
  get mapping() {
    const s = mapping.state;
    return {
      phase: s.phase,
      mapping: s.mapping,
      scans: s.status?.scans ?? 0,
      nodes: s.status?.nodes ?? 0,
      loopClosures: s.status?.loop_closures ?? 0,
      error: s.error,
      saved: s.saved ? { ...s.saved } : null,
    };
  },
  get localization() {
    const s = localization.status;
    return { method: s.method?.raw ?? null, family: s.method?.family ?? null, converged: s.converged, error: localization.lastError, globalRunning: localization.globalRunning };
  },
  get particles() {
    const layer = live.mapView.layers.particles;
    const set = layer.current;
    return { count: set?.count ?? 0, total: set?.total ?? 0, drawn: layer.drawn, setsDrawn: layer.setsDrawn };
  },
  get costmaps() {
    return { global: live.mapView.layers.costmap.cells, local: live.mapView.layers.localCostmap.cells };
  },
  get irReadings() {
    return live.mapView.layers.ir.count;
  },
  get zones() {
    return {
      mapId: zones.mapId,
      count: zones.zones.length,
      drawn: live.mapView.layers.zones.drawn,
      drawing: zones.drawing,
      vertices: zones.draft.vertices.length,
      problem: zones.draft.problem,
      error: zones.lastError,
    };
  },
  get robot() {
    const body = live.body;
    return { kinematics: live.status?.kinematics ?? null, body: body.kind, steering: live.steering };
  },
  get camera() {
    const box = (b: { x: number; y: number; w: number; h: number } | null | undefined) => (b ? { x: b.x, y: b.y, w: b.w, h: b.h } : null);
    const canvas = document.getElementById('camera-canvas') as HTMLCanvasElement | null;
    return {
      available: camera.available,
      kind: camera.info?.kind ?? null,
      subscribed: camera.subscribed,
      quality: camera.quality,
      lastFrameBytes: camera.lastFrameBytes,
      framesDrawn: camera.framesDrawn,
      framesDecoded: camera.queue.decoded,
      framesDropped: camera.queue.dropped,
      width: canvas?.width ?? 0,
      height: canvas?.height ?? 0,
      target: { status: camera.target.status, box: box(camera.target.box), range: camera.target.range_m ?? null },
      lastBox: box(camera.lastBox),
      drawing: camera.drawing,
      following: camera.following,
      head: camera.headAngles,
      error: camera.lastError,
    };
  },
  cameraToClient(x: number, y: number) {
    return camera.imageToClient(x, y);
  },
  get operator() {
    const v = operator.view;
    const holder = operator.holder;
    return {
      supported: operator.supported,
      state: v.state,
      holder: holder ? { tokenId: holder.tokenId, label: holder.label, role: holder.role, address: holder.address, since: holder.since } : null,
      me: operator.me,
      admin: operator.admin,
      line: v.line,
      buttons: { ...v.buttons },
      blocksCommands: v.blocksCommands,
      lostTo: operator.lostTo,
      error: operator.lastError,
      polls: operator.polls,
    };
  },
  get clients() {
    return {
      shown: clients.admin === true,
      open: clients.open,
      polling: clients.polling,
      polls: clients.polls,
      rows: clients.clients.map((c) => ({ id: c.id, kind: c.kind, label: c.label, role: c.role, address: c.address, topics: [...c.topics], bytesSent: c.bytesSent, dropped: c.dropped })),
      error: clients.lastError,
    };
  },
};

/** /robot (REST or the status topic): every panel that shows part of it. */
function onRobotStatus(status: RobotStatus): void {
  live.onStatus(status);
  camera.onStatus(status);
  showEstop(status.estop);
  mapping.onStatus(status);
  localization.onStatus(status);
  const family = localization.status.method?.family;
  // A cloud arriving after this (the filter started again) is drawn again.
  if (family && family !== 'particle_filter' && !localization.globalRunning) dropParticles();
}

/** An `ir_safety` event: the IR ring saw something in a safety zone and the robot reacted. */
function showIrSafety(detail: unknown): void {
  const d = (detail && typeof detail === 'object' ? detail : {}) as { sensor?: unknown; zone?: unknown; reaction?: unknown };
  toast(`IR safety: sensor ${String(d.sensor ?? '?')} in the ${String(d.zone ?? '?')} zone → ${String(d.reaction ?? '?')}`, 'error');
}

/** A `fault` event: a sensor the robot needs fell silent or its device failed; the robot stopped. */
function showFault(detail: unknown): void {
  const d = (detail && typeof detail === 'object' ? detail : {}) as { sensor?: unknown; reason?: unknown };
  toast(`${String(d.sensor ?? 'a sensor')}: ${String(d.reason ?? 'fault')}, the robot stopped`, 'error');
}

// ---- connection ----

function showConnection(state: ConnectionState, detail: string): void {
  connectionState = state;
  const el = byId('connection');
  el.dataset.state = state;
  const labels: Record<ConnectionState, string> = {
    connecting: 'connecting…',
    connected: 'connected',
    disconnected: 'disconnected',
    auth_error: 'auth error',
  };
  byId('connection-label').textContent = labels[state];
  byId('connection-detail').textContent = state === 'disconnected' && detail ? detail : '';
  el.title = detail;
  document.body.classList.toggle('offline', state !== 'connected');
  if (state === 'auth_error') showLogin('The server refused the token (401 unauthorized). Enter a valid token.');
  if (state === 'connected') {
    void loadServerInfo();
    void nav.load();
    void mapping.connected();
    void localization.connected();
    void zones.connected();
    void camera.connected();
    void cloud3d.connected();
    operator.connected();
    void clients.connected();
    if (ipabd.enabled) void ipabd.refresh();
    if (currentPage !== 'live') void refreshPage(currentPage);
  } else {
    camera.disconnected();
    operator.disconnected();
    clients.disconnected();
  }
}

async function loadServerInfo(): Promise<void> {
  try {
    const health = await api.health();
    byId('server-info').textContent = `${health.backend} · v${health.version}`;
    // A server started anew (uptime went back) has none of the obstacles dropped before.
    const startedAt = Date.now() / 1000 - health.uptime_s;
    if (serverStartedAt !== null && Math.abs(startedAt - serverStartedAt) > 3) {
      nav.clearObstacles();
      // Nor need it refuse the controllers the old one did.
      nav.serverChanged();
    }
    serverStartedAt = startedAt;
  } catch {
    // informative only
  }
  try {
    onRobotStatus(await api.robot());
  } catch (error) {
    if (error instanceof ApiError && error.status === 401) showLogin(`The server refused the token: ${error.describe()}`);
  }
}

// ---- login ----

function showLogin(message: string | null): void {
  const login = byId('login');
  login.hidden = false;
  const error = byId('auth-error');
  error.hidden = !message;
  error.textContent = message ?? '';
  const input = byId<HTMLInputElement>('login-token');
  input.value = '';
  input.focus();
}

byId('login-form').addEventListener('submit', (e) => {
  e.preventDefault();
  const value = byId<HTMLInputElement>('login-token').value.trim();
  if (!value) return;
  token = value;
  saveToken(token);
  api.setToken(token);
  operator.tokenChanged();
  clients.tokenChanged();
  byId('login').hidden = true;
  void start();
});

byId('signout').addEventListener('click', () => {
  forgetToken();
  token = '';
  api.setToken('');
  operator.tokenChanged();
  clients.tokenChanged();
  stream.stop();
  showLogin(null);
});

// ---- e-stop ----

function showEstop(engaged: boolean): void {
  estopEngaged = engaged;
  const state = byId('estop-state');
  state.dataset.engaged = String(engaged);
  state.textContent = engaged ? 'E-STOP ENGAGED' : 'e-stop released';
  byId('estop-overlay').hidden = !engaged;
  document.body.classList.toggle('estopped', engaged);
}

async function setEstop(engaged: boolean): Promise<void> {
  try {
    const reply = await api.estop(engaged);
    showEstop(reply.estop);
    live.setEstop(reply.estop);
    // The mode follows on the next status frame (1 Hz); ask now so the panel does not lag.
    window.setTimeout(() => void api.robot().then((status) => live.onStatus(status), () => {}), 150);
    toast(reply.estop ? 'E-stop engaged' : 'E-stop released', reply.estop ? 'error' : 'ok');
  } catch (error) {
    lastError = errorText(error);
    toast(`E-stop request failed: ${errorText(error)}`, 'error');
  }
}

byId('estop').addEventListener('click', () => void setEstop(true));
byId('estop-release').addEventListener('click', () => void setEstop(false));

// ---- tabs ----

async function refreshPage(page: string): Promise<void> {
  if (page === 'maps') await maps.refresh();
  if (page === 'runs') await runs.refresh();
  if (page === '3d') await cloud3d.show();
}

function showPage(page: string): void {
  currentPage = page;
  for (const tab of document.querySelectorAll<HTMLElement>('.tab')) {
    const active = tab.dataset.page === page;
    tab.classList.toggle('active', active);
    tab.setAttribute('aria-selected', String(active));
  }
  for (const section of document.querySelectorAll<HTMLElement>('.page')) {
    section.classList.toggle('active', section.id === `page-${page}`);
  }
  if (page !== 'live') live.teleop.releaseAll();
  live.teleop.enabled = page === 'live';
  nav.enabled = page === 'live';
  zones.enabled = page === 'live';
  camera.setVisible(page === 'live');
  clients.setVisible(page === 'live');
  if (page !== 'live') {
    nav.setMode(null);
    zones.stop();
  }
  if (page !== '3d') cloud3d.hide();
  if (window.location.hash !== `#${page}`) window.history.replaceState(null, '', `#${page}`);
  void refreshPage(page);
}

for (const tab of document.querySelectorAll<HTMLElement>('.tab')) {
  tab.addEventListener('click', () => showPage(tab.dataset.page ?? 'live'));
}

// ---- start ----

async function start(): Promise<void> {
  if (!token) {
    showLogin(null);
    return;
  }
  // Ask REST first so a bad token is reported at once instead of as a failing socket.
  try {
    await api.robot();
  } catch (error) {
    if (error instanceof ApiError && error.status === 401) {
      showConnection('auth_error', error.describe());
      showLogin(`The server refused the token: ${error.describe()}`);
      return;
    }
    // Unreachable or another error: the stream keeps retrying with backoff.
  }
  stream.restart();
}

const initial = window.location.hash.replace('#', '');
if (initial === 'maps' || initial === 'runs' || initial === '3d') showPage(initial);
window.addEventListener('unhandledrejection', (e) => {
  lastError = errorText(e.reason);
});
void start();
