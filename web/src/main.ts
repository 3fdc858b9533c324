// Dashboard entry: sign-in (login view, token kept per tab or remembered), REST client, stream,
// pages, the Link card and the disconnect banner, e-stop (stream first, REST as the fallback) and
// the test hooks (window.__mobot).

import './style.css';
import { ApiClient } from './api';
import type { RobotStatus } from './api';
import { ApiError, errorText } from './apierror';
import { basePath, forgetToken, saveToken, storedToken, streamUrl, takeUrlToken } from './auth';
import { CameraPanel } from './camera_panel';
import { ClientsPanel } from './clients_panel';
import { localWallMs } from './clock_offset';
import { EstopChannel, EstopRefused } from './estop';
import type { EstopAck } from './estop';
import type { Pose2D } from './frames';
import type { SonarReading } from './map/layers/sonar';
import { LivePage } from './pages/live';
import type { PoseData } from './pages/live';
import { covarianceEllipse, headingSigma } from './goals';
import { NavigationPanel } from './nav';
import type { NavError, NavMode } from './nav';
import { IpabdOverlay } from './ipabdoverlay';
import { bannerView, LinkBanner } from './link_banner';
import { LinkPanel } from './link_panel';
import type { SeriesSummary } from './link_panel';
import type { SeriesKey } from './link';
import { loginErrorText, parseWhoami, REVOKED_TEXT, roleTitle, signedInText, type SignedInAs } from './login';
import type { Role } from './login';
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
import { byId, dateTime, fmt, toast } from './ui';

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
  /**
   * Sign-in: a token is in use, its role (null: not read yet or unreadable), whether it is kept on
   * this device (localStorage) rather than for this tab, and the login view is shown.
   */
  readonly session: { signedIn: boolean; role: Role | null; remembered: boolean; loginShown: boolean; loginError: string | null };
  /**
   * The Link card: plot samples held (60 s at 4 Hz) and plots drawn; the newest sample's values
   * (ms): the ping round trip, the teleop echo's, the ages of the pose and scan on screen;
   * the clock offset (null: not measured) and the round trip of the pong it came from; bytes/s;
   * dropped frames (full-rate topics) and gaps on thinned ones; summary(seconds) of each series.
   */
  readonly link: {
    samples: number;
    drawn: number;
    pingRttMs: number | null;
    teleopRttMs: number | null;
    poseAgeMs: number | null;
    scanAgeMs: number | null;
    offsetMs: number | null;
    offsetRttMs: number | null;
    offsetMeasured: boolean;
    bytesPerSecond: number | null;
    dropped: number;
    thinnedGaps: number;
    summary(seconds: number): Record<SeriesKey, SeriesSummary>;
  };
  /** The disconnect banner: shown, its words, the reconnect attempt. */
  readonly banner: { shown: boolean; title: string; detail: string; attempt: number };
  /** Stream teleop: the last seq sent on this connection, echoes received, drives cut by the link. */
  readonly teleop: { seq: number; acks: number; interrupts: number };
  /** The last e-stop acknowledgement: state, how it went (stream or REST) and how long it took. */
  readonly estopAck: EstopAck | null;
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

let token = '';
/** A token is in use (the dashboard is shown); false while the login view is. */
let signedIn = false;
/** The token in use is kept on this device (localStorage), not only for this tab. */
let remembered = false;
let role: Role | null = null;
/** The stream was open at least once since sign-in: a close after that is an outage. */
let everConnected = false;
let lastConnectionDetail = '';
const api = new ApiClient(token, basePath());
let estopEngaged: boolean | null = null;
let lastEstopAck: EstopAck | null = null;
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
          link.onPose(meta.wallUs);
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
    scan: (scan, meta) => {
      live.onScan(scan);
      link.onScan(meta.wallUs);
    },
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
    serverError: (code, message, requestOp) => {
      // A refused e-stop request is reported by the e-stop button's own message.
      if (estop.onStreamError(code, message, requestOp)) return;
      lastError = `${code}: ${message}`;
      if (code === 'operator_busy') {
        // Teleop is the only stream op the lock guards; the card asks who drives now.
        toast(`Teleop refused: ${message}`, 'error');
        operator.commandRefused();
        return;
      }
      toast(`${message} (${code})`, 'error');
    },
    teleopAck: (ack) => {
      live.onTeleopAck(ack.v, ack.w, ack.seq, ack.rttMs);
      link.onTeleopAck(ack);
      operator.commandAccepted();
    },
    estopAck: (engaged) => {
      // An answer nothing waits for (the request already went by REST) still tells the state.
      if (!estop.onStreamAck(engaged)) showEstop(engaged);
    },
    pong: (pong) => link.onPong(pong),
  },
});

const live = new LivePage((command) => {
  const moving = command.v !== 0 || command.w !== 0;
  // Somebody else surely drives: nothing is sent (a held key would be refused 15 times a second);
  // a drive input says why, the release of one says nothing.
  if (operator.view.blocksCommands) {
    if (moving) lastError = operator.refuseLocally('Teleop') ?? lastError;
    return 'refused';
  }
  // Each command is a lease of TTL_MS: without a link it is dropped, never kept for later.
  if (stream.sendTeleop(command.v, command.w, TTL_MS)) return 'sent';
  if (moving) toast('Not connected: teleop is not sent', 'error');
  return 'offline';
});
const link = new LinkPanel(stream);
const banner = new LinkBanner(byId('link-banner'), byId('link-banner-title'), byId('link-banner-detail'));
const estop = new EstopChannel({
  streamSend: (engaged) => stream.connected && stream.send({ op: 'estop', engaged }),
  rest: async (engaged) => (await api.estop(engaged)).estop,
  now: () => performance.now(),
  setTimeout: (fn, ms) => window.setTimeout(fn, ms),
  clearTimeout: (handle) => window.clearTimeout(handle as number),
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
  get session() {
    const error = byId('auth-error');
    return { signedIn, role, remembered, loginShown: !byId('login').hidden, loginError: error.hidden ? null : error.textContent };
  },
  get link() {
    const now = localWallMs();
    const latest = link.monitor.latest();
    const offset = link.monitor.currentOffset(now);
    const gaps = link.gaps();
    return {
      samples: link.monitor.history().length,
      drawn: link.drawn,
      pingRttMs: latest?.pingRttMs ?? null,
      teleopRttMs: latest?.teleopRttMs ?? null,
      poseAgeMs: latest?.poseAgeMs ?? null,
      scanAgeMs: latest?.scanAgeMs ?? null,
      offsetMs: offset?.offsetMs ?? null,
      offsetRttMs: offset?.rttMs ?? null,
      offsetMeasured: link.monitor.offsetMeasured,
      bytesPerSecond: link.monitor.bytesPerSecond(),
      dropped: gaps.dropped,
      thinnedGaps: gaps.thinned,
      summary: (seconds: number) => link.summary(seconds),
    };
  },
  get banner() {
    return { ...banner.view, attempt: stream.attempt };
  },
  get teleop() {
    return { seq: stream.teleopSeq, acks: stream.teleopAcks, interrupts: live.teleop.interrupts };
  },
  get estopAck() {
    return lastEstopAck ? { ...lastEstopAck } : null;
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
  lastConnectionDetail = detail;
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
  if (state === 'connected') {
    everConnected = true;
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
    // Whatever was being driven stops by its lease; nothing held now drives again on its own.
    live.teleop.interrupt();
    link.disconnected();
    // An e-stop sent on the closed stream may be lost: REST carries it now.
    estop.onDisconnected();
    camera.disconnected();
    operator.disconnected();
    clients.disconnected();
  }
  if (state === 'auth_error' && signedIn) {
    const why = stream.authFailure === 'revoked' ? REVOKED_TEXT : 'The server refused the token (401 unauthorized). Sign in with a valid token.';
    signOut(why, true);
  }
  updateBanner();
}

/** The disconnect banner, from the stream's state and its reconnect schedule. */
function updateBanner(): void {
  banner.render(
    bannerView({
      state: signedIn ? connectionState : 'auth_error',
      everConnected,
      attempt: stream.attempt,
      nextInMs: stream.nextAttemptAt === null ? null : stream.nextAttemptAt - performance.now(),
      reason: lastConnectionDetail,
      leaseMs: TTL_MS,
    }),
  );
}
// The countdown to the next attempt moves.
window.setInterval(updateBanner, 250);

async function loadServerInfo(): Promise<void> {
  const asked = token;
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
    // A token the server took at sign-in and refuses now was revoked or has expired (its
    // stream's 4401 may come just after this answer). Only for the token it asked with: one
    // signed out meanwhile is not signed out again for a request made without it.
    if (error instanceof ApiError && error.status === 401 && signedIn && token === asked) {
      signOut(REVOKED_TEXT, true);
    }
  }
}

// ---- sign-in ----

/** The login view, with why it is shown (null: just signed out, or no token yet). */
function showLogin(message: string | null): void {
  document.body.classList.add('signed-out');
  byId('login').hidden = false;
  const error = byId('auth-error');
  error.hidden = !message;
  error.textContent = message ?? '';
  const input = byId<HTMLInputElement>('login-token');
  input.value = '';
  input.focus();
}

function showRole(who: SignedInAs | null): void {
  role = who?.role ?? null;
  const el = byId('session-role');
  el.textContent = role ?? '';
  el.dataset.role = role ?? '';
  const as = who ? `Signed in as ${signedInText(who)}, token #${who.tokenId}${who.expiresAt !== null ? `, valid until ${dateTime(who.expiresAt)}` : ''}. ` : '';
  el.title = `${as}This token's role — ${roleTitle(role)}. ${remembered ? 'Remembered on this device' : 'Kept for this tab only'} until you sign out.`;
}

/**
 * Uses `candidate` if the server takes it (GET /api/v1/robot is not 401): kept per `remember`,
 * its role read and shown, the stream opened. `source` says where it came from: a token typed in
 * must be confirmed by the server; a stored one (or one from the URL) is used while the server
 * cannot be reached, the stream retrying meanwhile.
 */
async function signIn(candidate: string, remember: boolean, source: 'form' | 'url' | 'stored'): Promise<boolean> {
  const probe = new ApiClient(candidate, basePath());
  let status: RobotStatus | null = null;
  try {
    status = await probe.robot();
  } catch (error) {
    const refused = error instanceof ApiError && error.status === 401;
    if (refused || source === 'form') {
      // A stored token the server refuses is of no use any more.
      if (refused && source !== 'form') forgetToken();
      if (refused) showConnection('auth_error', errorText(error));
      showLogin(loginErrorText(error));
      return false;
    }
  }
  token = candidate;
  remembered = remember;
  saveToken(token, remember);
  api.setToken(token);
  signedIn = true;
  everConnected = false;
  operator.tokenChanged();
  clients.tokenChanged();
  byId('login').hidden = true;
  byId('auth-error').hidden = true;
  document.body.classList.remove('signed-out');
  showRole(null);
  if (status) onRobotStatus(status);
  void api.whoami().then(parseWhoami, () => null).then((who) => {
    if (token !== candidate) return; // signed out (or in again) meanwhile
    showRole(who);
    if (who) operator.identify(who.tokenId);
    if (source === 'form' && who) toast(`Signed in as ${signedInText(who)}`, 'ok');
  });
  stream.restart();
  if (currentPage !== 'live') void refreshPage(currentPage);
  return true;
}

/**
 * Forgets the token (this tab and this device), closes the stream and shows the login view;
 * `refused`: because the server turned the token down (the connection then reads auth_error).
 */
function signOut(message: string | null, refused = false): void {
  forgetToken();
  token = '';
  signedIn = false;
  remembered = false;
  api.setToken('');
  showRole(null);
  operator.tokenChanged();
  clients.tokenChanged();
  stream.stop();
  if (refused) showConnection('auth_error', message ?? '');
  showLogin(message);
  updateBanner();
}

byId('login-form').addEventListener('submit', (e) => {
  e.preventDefault();
  const value = byId<HTMLInputElement>('login-token').value.trim();
  if (!value) {
    showLogin('Enter a token.');
    return;
  }
  const submit = byId<HTMLButtonElement>('login-submit');
  submit.disabled = true;
  submit.textContent = 'Checking…';
  void signIn(value, byId<HTMLInputElement>('login-remember').checked, 'form').finally(() => {
    submit.disabled = false;
    submit.textContent = 'Sign in';
  });
});

byId('signout').addEventListener('click', () => signOut(null));

// ---- e-stop ----

function showEstop(engaged: boolean, ack: EstopAck | null = null): void {
  estopEngaged = engaged;
  const state = byId('estop-state');
  state.dataset.engaged = String(engaged);
  state.textContent = engaged ? 'E-STOP ENGAGED' : 'e-stop released';
  if (ack) {
    state.dataset.via = ack.via;
    state.title = `${engaged ? 'Engaged' : 'Released'} at ${new Date().toLocaleTimeString(undefined, { hour12: false })}: acknowledged ${ack.via === 'stream' ? 'on the stream' : 'by REST'} in ${fmt(ack.elapsedMs, 0)} ms`;
  }
  byId('estop-overlay').hidden = !engaged;
  document.body.classList.toggle('estopped', engaged);
}

async function setEstop(engaged: boolean): Promise<void> {
  try {
    const ack = await estop.set(engaged);
    lastEstopAck = ack;
    showEstop(ack.engaged, ack);
    live.setEstop(ack.engaged);
    // The mode follows on the next status frame (1 Hz); ask now so the panel does not lag.
    window.setTimeout(() => void api.robot().then((status) => live.onStatus(status), () => {}), 150);
    const how = `acknowledged ${ack.via === 'stream' ? 'on the stream' : 'by REST'} in ${fmt(ack.elapsedMs, 0)} ms`;
    toast(`${ack.engaged ? 'E-stop engaged' : 'E-stop released'} — ${how}`, ack.engaged ? 'error' : 'ok');
  } catch (error) {
    const text = error instanceof EstopRefused ? `${error.message} (${error.code})` : errorText(error);
    lastError = error instanceof EstopRefused ? `${error.code}: ${error.message}` : text;
    toast(`E-stop request failed: ${text}`, 'error');
  }
}

byId('estop').addEventListener('click', () => void setEstop(true));
byId('estop-release').addEventListener('click', () => void setEstop(false));

// ---- tabs ----

async function refreshPage(page: string): Promise<void> {
  // Signed out, nothing is asked of the server.
  if (!signedIn) return;
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
  link.setVisible(page === 'live');
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

/** A ?token= on the URL (taken once, off the address bar), else a kept one, else the login view. */
function start(): void {
  const fromUrl = takeUrlToken();
  const kept = storedToken();
  if (fromUrl) void signIn(fromUrl, false, 'url');
  else if (kept) void signIn(kept.token, kept.remembered, 'stored');
  else showLogin(null);
}

const initial = window.location.hash.replace('#', '');
if (initial === 'maps' || initial === 'runs' || initial === '3d') showPage(initial);
window.addEventListener('unhandledrejection', (e) => {
  lastError = errorText(e.reason);
});
start();
