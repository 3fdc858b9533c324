// The Camera card of the Live page, shown only when GET /api/v1/camera answers 200: the live image
// (the `camera` topic, binary JPEG frames, thinned to CAMERA_MAX_RATE_HZ and subscribed only while
// the Live page shows the card), a box drawn on it with the mouse starts tracking (POST
// /api/v1/tracking), the tracked window from the `target` topic drawn over the image in the colour
// of its status, Stop tracking, Follow at a distance / Stop following (POST / DELETE
// /api/v1/follow), and pan/tilt jogs for a pan-tilt head (PUT /api/v1/camera/pan_tilt). The logic
// is camera.ts (bodies, overlay, jogs, follow distance, refusals), camera_box.ts (the box drawing)
// and camera_frames.ts (decoding without a backlog); this renders them and talks to the server.

import { ApiError } from './apierror';
import type { ApiClient, RobotStatus } from './api';
import {
  cameraErrorText,
  followEventToast,
  headLimits,
  IDLE_TARGET,
  JOG_DIRECTIONS,
  jogPanTilt,
  jogsAvailable,
  parseCameraInfo,
  parseFollowDistance,
  parseTarget,
  TARGET_COLORS,
  targetDetail,
  targetOverlay,
} from './camera';
import type { CameraInfo, JogDirection, PanTilt, TargetState } from './camera';
import { BoxDraft, imageToClient } from './camera_box';
import type { ImageBox } from './camera_box';
import { LatestFrameQueue } from './camera_frames';
import { byId, deg, fmt, toast } from './ui';

/** The image rate asked of the server: a thin link is not flooded with JPEGs. */
export const CAMERA_MAX_RATE_HZ = 10;
/** No frame for this long: the image is marked stale. */
const STALE_MS = 3000;
/** The head moves under the tracker too: its pan/tilt is asked again this often while shown. */
const HEAD_POLL_MS = 2000;
const DRAFT_COLOR = '#38bdf8';

export interface CameraPanelHooks {
  /** Sends one stream op; false when the socket is not open. */
  send(message: object): boolean;
  /** Whether the stream is connected. */
  connected(): boolean;
  /** Following started or stopped: the robot's mode should be asked now, not at the next 1 Hz status. */
  refreshStatus(): void;
}

export class CameraPanel {
  /** GET /camera answered 200 with a camera. */
  available = false;
  info: CameraInfo | null = null;
  target: TargetState = IDLE_TARGET;
  /** Whether /robot says the robot follows (or a Follow was just accepted). */
  following = false;
  framesDrawn = 0;
  /** The last box sent with POST /tracking (image pixels). */
  lastBox: ImageBox | null = null;
  lastError: string | null = null;
  /** The camera topic is subscribed on the current connection. */
  subscribed = false;
  /** The JPEG quality cap asked of the stream (camera_quality), 0 for the camera's own. */
  quality = 0;
  /** The size of the last frame received, bytes. */
  lastFrameBytes = 0;
  readonly queue: LatestFrameQueue<ImageBitmap>;
  private readonly canvas: HTMLCanvasElement;
  private readonly ctx: CanvasRenderingContext2D;
  private readonly draft = new BoxDraft();
  private bitmap: ImageBitmap | null = null;
  private newFrame = false;
  private lastFrameAt = 0;
  private topics: readonly string[] = [];
  private visible = true;
  private dirty = true;
  /** The head's pan/tilt as last reported or commanded (commands go from here, not from a stale poll). */
  private head: PanTilt | null = null;
  private headCommandAt = 0;
  private busy = { tracking: false, follow: false, jog: false };
  private probing: Promise<void> | null = null;

  constructor(
    private readonly api: ApiClient,
    private readonly hooks: CameraPanelHooks,
  ) {
    this.canvas = byId<HTMLCanvasElement>('camera-canvas');
    const ctx = this.canvas.getContext('2d');
    if (!ctx) throw new Error('canvas 2D is not available');
    this.ctx = ctx;
    this.queue = new LatestFrameQueue<ImageBitmap>({
      decode: (bytes) => createImageBitmap(new Blob([bytes as Uint8Array<ArrayBuffer>], { type: 'image/jpeg' })),
      deliver: (bitmap) => this.showBitmap(bitmap),
      discard: (bitmap) => bitmap.close(),
      failed: (error) => console.warn('mobot: a camera frame did not decode', error),
    });
    this.bindPointer();
    for (const direction of JOG_DIRECTIONS) {
      document.querySelector(`[data-jog=${direction}]`)?.addEventListener('click', () => void this.jog(direction));
    }
    byId<HTMLSelectElement>('camera-quality').addEventListener('change', (e) => this.setQuality(Number((e.target as HTMLSelectElement).value)));
    byId('tracking-stop').addEventListener('click', () => void this.stopTracking());
    byId('follow-form').addEventListener('submit', (e) => {
      e.preventDefault();
      void this.follow();
    });
    byId('follow-stop').addEventListener('click', () => void this.stopFollowing());
    byId<HTMLInputElement>('follow-distance').addEventListener('input', (e) => (e.target as HTMLElement).removeAttribute('aria-invalid'));
    const enlarge = byId('camera-enlarge');
    enlarge.addEventListener('click', () => {
      const large = byId('camera-panel').classList.toggle('large');
      enlarge.setAttribute('aria-pressed', String(large));
    });
    window.setInterval(() => this.renderCard(), 1000);
    window.setInterval(() => void this.pollHead(), HEAD_POLL_MS);
    const loop = () => {
      requestAnimationFrame(loop);
      if (this.dirty) {
        this.dirty = false;
        this.draw();
      }
    };
    requestAnimationFrame(loop);
    this.renderCard();
  }

  // ---- connection and visibility ----

  /** On (re)connect: does this robot have a camera (GET /camera), and what is tracked. */
  async connected(): Promise<void> {
    this.probing ??= (async () => {
      try {
        const info = parseCameraInfo(await this.api.camera());
        this.setInfo(info);
      } catch (error) {
        // 404 (no_camera, or not_found on a server without the endpoint): no camera. Otherwise
        // (unreachable, 5xx) keep what we knew; the next connect asks again.
        if (error instanceof ApiError && error.status === 404) this.setInfo(null);
      } finally {
        this.probing = null;
      }
      if (this.available) await this.refreshTracking();
      this.syncSubscription();
      this.renderCard();
    })();
    return this.probing;
  }

  /** The stream dropped: the server forgets our subscriptions. */
  disconnected(): void {
    this.subscribed = false;
    // The next connection's hello says what it offers.
    this.topics = [];
    this.draft.cancel();
    this.renderCard();
  }

  /** The hello's topics (a new connection: nothing is subscribed on it yet). */
  onHello(topics: readonly string[]): void {
    this.topics = topics;
    this.subscribed = false;
    this.syncSubscription();
  }

  /** The Live page is shown (the image is only streamed then). */
  setVisible(visible: boolean): void {
    this.visible = visible;
    if (!visible) this.cancelDraft();
    this.syncSubscription();
  }

  private setInfo(info: CameraInfo | null): void {
    this.info = info;
    this.available = info !== null;
    if (info) {
      // A jog just sent is newer than what the head reported before it.
      if (!this.head || performance.now() - this.headCommandAt > HEAD_POLL_MS) this.head = { pan: info.pan ?? 0, tilt: info.tilt ?? 0 };
      // Until a frame says otherwise, the canvas has the advertised image size.
      if (!this.bitmap && info.width > 0 && info.height > 0) this.resizeCanvas(info.width, info.height);
    } else {
      this.target = IDLE_TARGET;
      this.bitmap?.close();
      this.bitmap = null;
    }
    byId('camera-panel').hidden = !this.available;
    this.dirty = true;
  }

  private syncSubscription(): void {
    const wanted = this.available && this.visible && this.topics.includes('camera') && this.hooks.connected();
    if (wanted && !this.subscribed) {
      this.queue.resume();
      this.subscribed = this.hooks.send(this.subscription());
    } else if (!wanted && this.subscribed) {
      this.hooks.send({ op: 'unsubscribe', topics: ['camera'] });
      this.subscribed = false;
      this.queue.dispose();
    }
    this.renderCard();
  }

  private subscription(): Record<string, unknown> {
    const request: Record<string, unknown> = { op: 'subscribe', topics: ['camera'], encoding: 'binary', max_rate_hz: CAMERA_MAX_RATE_HZ };
    if (this.quality > 0) request.camera_quality = this.quality;
    return request;
  }

  /** A new quality cap: subscribing again replaces the subscription's. */
  private setQuality(quality: number): void {
    this.quality = Number.isInteger(quality) && quality >= 1 && quality <= 100 ? quality : 0;
    if (this.subscribed) this.subscribed = this.hooks.send(this.subscription());
  }

  // ---- stream data ----

  /** A camera frame (JPEG bytes). */
  onFrame(jpeg: Uint8Array): void {
    if (!this.available || !this.subscribed) return;
    this.lastFrameAt = performance.now();
    this.lastFrameBytes = jpeg.byteLength;
    this.queue.push(jpeg);
  }

  /** The `target` topic (or a tracking reply). */
  onTarget(data: unknown): void {
    const state = parseTarget(data);
    if (!state) return;
    this.target = state;
    this.dirty = true;
    this.renderCard();
  }

  /** /robot (REST or the status topic): the mode says whether the robot follows. */
  onStatus(status: RobotStatus): void {
    if (this.busy.follow) return;
    const following = status.mode === 'following';
    if (following === this.following) return;
    this.following = following;
    this.renderCard();
  }

  /** A `follow` event: following ended (the reason says why) or started. */
  onFollowEvent(detail: unknown): void {
    const message = followEventToast(detail);
    if (!message) return;
    this.following = false;
    toast(message.text, message.kind);
    this.renderCard();
    this.hooks.refreshStatus();
  }

  // ---- requests ----

  async refreshTracking(): Promise<void> {
    try {
      this.onTarget(await this.api.tracking());
    } catch {
      // No tracking on this server (404) or unreachable: the topic will say.
    }
  }

  private async startTracking(box: ImageBox): Promise<void> {
    if (this.busy.tracking) return;
    this.busy.tracking = true;
    this.lastBox = box;
    this.showError(null);
    this.renderCard();
    try {
      const reply = parseTarget(await this.api.startTracking(box));
      this.target = reply ?? { status: 'tracking', box };
      toast(`Tracking the ${box.w}×${box.h} px box`, 'ok');
    } catch (error) {
      this.refused('Tracking', error);
    } finally {
      this.busy.tracking = false;
      this.dirty = true;
      this.renderCard();
    }
  }

  private async stopTracking(): Promise<void> {
    if (this.busy.tracking) return;
    this.busy.tracking = true;
    this.showError(null);
    this.renderCard();
    try {
      const reply = parseTarget(await this.api.stopTracking());
      this.target = reply ?? IDLE_TARGET;
      toast('Tracking stopped', 'info');
    } catch (error) {
      this.refused('Stop tracking', error);
    } finally {
      this.busy.tracking = false;
      this.dirty = true;
      this.renderCard();
    }
  }

  private async follow(): Promise<void> {
    if (this.busy.follow) return;
    const input = byId<HTMLInputElement>('follow-distance');
    const parsed = parseFollowDistance(input.value);
    if ('problem' in parsed) {
      // Refused here: nothing is sent.
      input.setAttribute('aria-invalid', 'true');
      this.showError(parsed.problem);
      this.renderCard();
      return;
    }
    this.busy.follow = true;
    this.showError(null);
    this.renderCard();
    try {
      await this.api.follow(parsed.distance);
      this.following = true;
      toast(`Following the target at ${fmt(parsed.distance, 1)} m`, 'ok');
    } catch (error) {
      this.refused('Follow', error);
    } finally {
      this.busy.follow = false;
      this.renderCard();
      this.hooks.refreshStatus();
    }
  }

  private async stopFollowing(): Promise<void> {
    if (this.busy.follow) return;
    this.busy.follow = true;
    this.showError(null);
    this.renderCard();
    try {
      await this.api.stopFollowing();
      this.following = false;
      toast('Following stopped', 'info');
    } catch (error) {
      this.refused('Stop following', error);
    } finally {
      this.busy.follow = false;
      this.renderCard();
      this.hooks.refreshStatus();
    }
  }

  private async jog(direction: JogDirection): Promise<void> {
    const info = this.info;
    if (!info || info.kind !== 'pan_tilt' || this.busy.jog) return;
    const current = this.head ?? { pan: info.pan ?? 0, tilt: info.tilt ?? 0 };
    const next = jogPanTilt(current, direction, headLimits(info));
    this.busy.jog = true;
    this.head = next;
    this.headCommandAt = performance.now();
    this.showError(null);
    this.renderCard();
    try {
      const reply = (await this.api.setPanTilt(next.pan, next.tilt)) as { pan?: unknown; tilt?: unknown } | undefined;
      // The head's answer (where it went) when it gives one; else where it was sent.
      if (reply && typeof reply.pan === 'number' && typeof reply.tilt === 'number') this.head = { pan: reply.pan, tilt: reply.tilt };
      this.headCommandAt = performance.now();
    } catch (error) {
      this.head = current;
      this.refused('Pan/tilt', error);
    } finally {
      this.busy.jog = false;
      this.renderCard();
    }
  }

  /** The head's pan/tilt (the tracker may move it): asked while the card is shown on a pan-tilt camera. */
  private async pollHead(): Promise<void> {
    if (!this.available || !this.visible || this.info?.kind !== 'pan_tilt' || this.busy.jog || !this.hooks.connected()) return;
    try {
      const info = parseCameraInfo(await this.api.camera());
      if (info && !this.busy.jog && performance.now() - this.headCommandAt > HEAD_POLL_MS) this.head = { pan: info.pan ?? 0, tilt: info.tilt ?? 0 };
      if (info) this.info = info;
      this.renderCard();
    } catch {
      // the next poll asks again
    }
  }

  private refused(what: string, error: unknown): void {
    const text = cameraErrorText(error);
    this.showError(text);
    toast(`${what}: ${text}`, 'error');
  }

  private showError(message: string | null): void {
    this.lastError = message;
    const box = byId('camera-error');
    box.hidden = !message;
    box.textContent = message ?? '';
  }

  // ---- drawing a box ----

  private bindPointer(): void {
    const canvas = this.canvas;
    let pointer: number | null = null;
    canvas.addEventListener('pointerdown', (e) => {
      if (e.button !== 0 || pointer !== null || !this.available) return;
      if (!this.draft.press(e.clientX, e.clientY, canvas.getBoundingClientRect(), canvas.width, canvas.height)) return;
      pointer = e.pointerId;
      canvas.setPointerCapture(e.pointerId);
      canvas.classList.add('drawing');
      e.preventDefault();
      this.dirty = true;
    });
    canvas.addEventListener('pointermove', (e) => {
      if (e.pointerId !== pointer) return;
      this.draft.move(e.clientX, e.clientY, canvas.getBoundingClientRect());
      this.dirty = true;
    });
    canvas.addEventListener('pointerup', (e) => {
      if (e.pointerId !== pointer) return;
      pointer = null;
      canvas.classList.remove('drawing');
      const result = this.draft.release(e.clientX, e.clientY, canvas.getBoundingClientRect());
      this.dirty = true;
      if (result.kind === 'refused') {
        this.showError(result.reason);
        this.renderCard();
      } else if (result.kind === 'box') {
        void this.startTracking(result.box);
      }
      // A click (no drag) sends nothing.
    });
    const cancel = (e: PointerEvent) => {
      if (e.pointerId !== pointer) return;
      pointer = null;
      canvas.classList.remove('drawing');
      this.cancelDraft();
    };
    canvas.addEventListener('pointercancel', cancel);
    canvas.addEventListener('lostpointercapture', cancel);
    window.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && this.draft.active) this.cancelDraft();
    });
  }

  private cancelDraft(): void {
    if (this.draft.cancel().kind !== 'none') this.dirty = true;
  }

  /** The head's pan/tilt (rad) as last reported or commanded; null without a pan-tilt head. */
  get headAngles(): PanTilt | null {
    return this.info?.kind === 'pan_tilt' && this.head ? { ...this.head } : null;
  }

  /** Whether a box is being drawn. */
  get drawing(): boolean {
    return this.draft.active;
  }

  /** Image pixels -> client (viewport) CSS pixels, for the browser test's mouse. */
  imageToClient(x: number, y: number): [number, number] {
    return imageToClient(x, y, this.canvas.getBoundingClientRect(), this.canvas.width, this.canvas.height);
  }

  // ---- image ----

  private showBitmap(bitmap: ImageBitmap): void {
    this.bitmap?.close();
    this.bitmap = bitmap;
    this.newFrame = true;
    if (bitmap.width !== this.canvas.width || bitmap.height !== this.canvas.height) {
      // A box being drawn is in the old image's pixels.
      this.cancelDraft();
      this.resizeCanvas(bitmap.width, bitmap.height);
    }
    this.dirty = true;
  }

  private resizeCanvas(width: number, height: number): void {
    this.canvas.width = width;
    this.canvas.height = height;
    this.dirty = true;
  }

  /** The image, the tracked window and the box being drawn, in image pixels. */
  private draw(): void {
    const { ctx, canvas } = this;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    if (this.bitmap) {
      ctx.drawImage(this.bitmap, 0, 0);
      if (this.newFrame) {
        this.newFrame = false;
        this.framesDrawn++;
      }
    } else {
      ctx.fillStyle = '#05080c';
      ctx.fillRect(0, 0, canvas.width, canvas.height);
    }
    // Lines and text keep their CSS size however large the image is shown.
    const cssWidth = canvas.getBoundingClientRect().width;
    const px = cssWidth > 0 ? canvas.width / cssWidth : 1;
    const overlay = targetOverlay(this.target);
    if (overlay) {
      const { x, y, w, h } = overlay.box;
      ctx.setLineDash(overlay.dash.map((d) => d * px));
      ctx.lineWidth = 2.5 * px;
      ctx.strokeStyle = overlay.color;
      ctx.strokeRect(x, y, w, h);
      ctx.setLineDash([]);
      ctx.font = `600 ${Math.round(12 * px)}px system-ui, sans-serif`;
      const textWidth = ctx.measureText(overlay.label).width;
      const labelH = 16 * px;
      const labelY = y >= labelH ? y - labelH : y + h;
      ctx.fillStyle = 'rgba(11, 15, 20, 0.75)';
      ctx.fillRect(x, labelY, textWidth + 8 * px, labelH);
      ctx.fillStyle = overlay.color;
      ctx.textBaseline = 'middle';
      ctx.fillText(overlay.label, x + 4 * px, labelY + labelH / 2);
    }
    const draft = this.draft.box;
    if (draft) {
      ctx.setLineDash([5 * px, 3 * px]);
      ctx.lineWidth = 2 * px;
      ctx.strokeStyle = DRAFT_COLOR;
      ctx.strokeRect(draft.x, draft.y, draft.w, draft.h);
      ctx.setLineDash([]);
      ctx.fillStyle = 'rgba(56, 189, 248, 0.12)';
      ctx.fillRect(draft.x, draft.y, draft.w, draft.h);
    }
    canvas.dataset.frames = String(this.framesDrawn);
    canvas.dataset.targetStatus = overlay?.status ?? 'idle';
  }

  // ---- card ----

  private renderCard(): void {
    if (!this.available) return;
    const info = this.info!;
    const status = byId('camera-target-status');
    status.dataset.status = this.target.status;
    status.textContent = this.target.status;
    status.style.color = this.target.status === 'idle' ? '' : TARGET_COLORS[this.target.status];
    byId('camera-target-detail').textContent = targetDetail(this.target);
    const size = this.bitmap ? `${this.bitmap.width}×${this.bitmap.height}` : `${info.width}×${info.height}`;
    const rate = Math.min(info.rate_hz || CAMERA_MAX_RATE_HZ, CAMERA_MAX_RATE_HZ);
    const infoLine = byId('camera-info');
    infoLine.textContent = `${info.kind.replace('_', '/')} · ${size} · ${fmt(rate, 0)} Hz`;
    infoLine.title = `camera ${info.kind}, ${size} px, ${fmt(info.rate_hz, 1)} Hz at the robot, at most ${CAMERA_MAX_RATE_HZ} Hz streamed here; ${this.queue.decoded} frames decoded, ${this.queue.dropped} skipped while decoding`;
    byId('camera-bytes').textContent = this.lastFrameBytes > 0 ? `${fmt(this.lastFrameBytes / 1024, 0)} kB a frame` : '';
    const stale = byId('camera-stale');
    const age = this.lastFrameAt ? performance.now() - this.lastFrameAt : Infinity;
    stale.hidden = this.subscribed && age < STALE_MS;
    stale.textContent = !this.hooks.connected() ? 'not connected' : this.lastFrameAt === 0 ? 'waiting for images…' : `no image for ${fmt(age / 1000, 0)} s`;

    const ptz = byId('camera-ptz');
    ptz.hidden = info.kind !== 'pan_tilt';
    if (info.kind === 'pan_tilt') {
      const head = this.head ?? { pan: info.pan ?? 0, tilt: info.tilt ?? 0 };
      const can = jogsAvailable(head, headLimits(info));
      for (const direction of JOG_DIRECTIONS) {
        const button = document.querySelector<HTMLButtonElement>(`[data-jog=${direction}]`);
        if (button) button.disabled = this.busy.jog || !can[direction];
      }
      byId('camera-pan-tilt').textContent = `pan ${deg(head.pan)} · tilt ${deg(head.tilt)}`;
    }
    byId<HTMLButtonElement>('tracking-stop').disabled = this.busy.tracking || this.target.status === 'idle';
    byId<HTMLButtonElement>('follow-start').disabled = this.busy.follow || this.following;
    byId<HTMLButtonElement>('follow-stop').disabled = this.busy.follow || !this.following;
  }
}
