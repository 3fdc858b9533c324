// Teleoperation inputs: on-screen joystick (pointer events), keyboard (WASD / arrows, hold to
// drive) and the Gamepad API (left stick). While any input is active a command is sent at
// SEND_HZ; when the last one is released a single zero command follows. A command that cannot be
// sent because the link is down is dropped, not kept, and ends the gesture: after the link is back
// the operator presses again (a key held through an outage, or the joystick held still, does not
// drive the robot again on its own with what they meant seconds ago).

export const SEND_HZ = 15;
export const TTL_MS = 300;
export const BASE_V = 0.5; // m/s at 100 %
export const BASE_W = 1.0; // rad/s at 100 %
const DEADZONE = 0.15;

export interface Command {
  v: number;
  w: number;
}

export type TeleopSource = 'joystick' | 'keyboard' | 'gamepad';

/** Keys held -> normalised command in [-1, 1] (forward, left positive). */
export function keysToAxes(keys: ReadonlySet<string>): { forward: number; turn: number } {
  const has = (...names: string[]) => names.some((n) => keys.has(n));
  const forward = (has('w', 'arrowup') ? 1 : 0) - (has('s', 'arrowdown') ? 1 : 0);
  const turn = (has('a', 'arrowleft') ? 1 : 0) - (has('d', 'arrowright') ? 1 : 0);
  return { forward, turn };
}

/** Joystick knob offset (pixels from the centre, screen y down) -> axes clipped to the unit disc. */
export function padToAxes(dx: number, dy: number, radius: number): { forward: number; turn: number } {
  let nx = dx / radius;
  let ny = dy / radius;
  const length = Math.hypot(nx, ny);
  if (length > 1) {
    nx /= length;
    ny /= length;
  }
  return { forward: -ny, turn: -nx };
}

export function applyDeadzone(value: number, deadzone = DEADZONE): number {
  if (Math.abs(value) < deadzone) return 0;
  return (Math.sign(value) * (Math.abs(value) - deadzone)) / (1 - deadzone);
}

const DRIVE_KEYS = new Set(['w', 'a', 's', 'd', 'arrowup', 'arrowdown', 'arrowleft', 'arrowright']);

export function isTypingTarget(target: EventTarget | null): boolean {
  if (!(target instanceof HTMLElement)) return false;
  if (target.isContentEditable) return true;
  const tag = target.tagName;
  if (tag === 'TEXTAREA' || tag === 'SELECT') return true;
  if (tag === 'INPUT') {
    const type = (target as HTMLInputElement).type;
    // Range sliders and buttons do not take text.
    return !['range', 'button', 'checkbox', 'radio', 'submit', 'reset', 'file', 'color'].includes(type);
  }
  return false;
}

/** sent; refused here (somebody else drives: nothing went out); offline (no link: dropped). */
export type SendResult = 'sent' | 'refused' | 'offline';

export interface TeleopOptions {
  /** Sends one command now, or says why it did not go. */
  send(command: Command): SendResult;
  /** Called on each change of the active command (null: idle). */
  onChange?(command: Command | null, source: TeleopSource | null): void;
  /** A drive was cut short by the link (see interrupt()). */
  onInterrupt?(): void;
}

export class TeleopController {
  speed = 1.0; // fraction of BASE_V / BASE_W
  enabled = true;
  private readonly keys = new Set<string>();
  private joystick: { forward: number; turn: number } | null = null;
  private gamepadIndex: number | null = null;
  private timer: number | undefined;
  private active = false;
  private lastSource: TeleopSource | null = null;
  /** Since an interrupt: the joystick and the gamepad drive again only after a release. */
  private joystickLatched = false;
  private gamepadLatched = false;
  /** Interrupts (link lost while driving), for the test hooks. */
  interrupts = 0;

  constructor(private readonly options: TeleopOptions) {
    window.addEventListener('keydown', this.onKeyDown);
    window.addEventListener('keyup', this.onKeyUp);
    window.addEventListener('blur', this.releaseAll);
    document.addEventListener('visibilitychange', () => {
      if (document.hidden) this.releaseAll();
    });
    window.addEventListener('gamepadconnected', (e) => {
      this.gamepadIndex = (e as GamepadEvent).gamepad.index;
    });
    window.addEventListener('gamepaddisconnected', (e) => {
      if ((e as GamepadEvent).gamepad.index === this.gamepadIndex) this.gamepadIndex = null;
      this.tick();
    });
    this.timer = window.setInterval(() => this.tick(), 1000 / SEND_HZ);
  }

  dispose(): void {
    window.clearInterval(this.timer);
    window.removeEventListener('keydown', this.onKeyDown);
    window.removeEventListener('keyup', this.onKeyUp);
    window.removeEventListener('blur', this.releaseAll);
  }

  get limits(): Command {
    return { v: BASE_V * this.speed, w: BASE_W * this.speed };
  }

  /** The joystick widget reports its axes, or null on release. */
  setJoystick(axes: { forward: number; turn: number } | null): void {
    if (axes === null) this.joystickLatched = false;
    else if (this.joystickLatched) return;
    this.joystick = axes;
    this.tick();
  }

  /**
   * The link went down: every input is let go without a command (none can be sent), and none
   * drives again until it is released and pressed anew.
   */
  interrupt(): void {
    this.keys.clear();
    // Only a joystick held now waits for its release (one not touched must work on the first drag);
    // the gamepad's latch lets go by itself at the first reading of a centred stick.
    this.joystickLatched = this.joystick !== null;
    this.joystick = null;
    this.gamepadLatched = true;
    if (!this.active) return;
    this.active = false;
    this.lastSource = null;
    this.interrupts++;
    this.options.onChange?.(null, null);
    this.options.onInterrupt?.();
  }

  releaseAll = (): void => {
    this.keys.clear();
    this.joystick = null;
    this.tick();
  };

  private onKeyDown = (e: KeyboardEvent): void => {
    if (!this.enabled || e.ctrlKey || e.metaKey || e.altKey || isTypingTarget(e.target)) return;
    const key = e.key.toLowerCase();
    if (!DRIVE_KEYS.has(key)) return;
    e.preventDefault();
    // Auto-repeat: a key still held after an interrupt repeats, and must be pressed again.
    if (e.repeat || this.keys.has(key)) return;
    this.keys.add(key);
    this.tick();
  };

  private onKeyUp = (e: KeyboardEvent): void => {
    const key = e.key.toLowerCase();
    if (!this.keys.delete(key)) return;
    e.preventDefault();
    this.tick();
  };

  private gamepadAxes(): { forward: number; turn: number } | null {
    if (typeof navigator.getGamepads !== 'function') return null;
    const pads = navigator.getGamepads();
    const pad =
      (this.gamepadIndex !== null ? pads[this.gamepadIndex] : null) ??
      pads.find((p): p is Gamepad => !!p && p.connected && p.axes.length >= 2) ??
      null;
    if (!pad || pad.axes.length < 2) return null;
    const turn = -applyDeadzone(pad.axes[0] ?? 0);
    const forward = -applyDeadzone(pad.axes[1] ?? 0);
    if (forward === 0 && turn === 0) {
      this.gamepadLatched = false;
      return null;
    }
    return this.gamepadLatched ? null : { forward, turn };
  }

  /** The command the inputs ask for now, or null when none is active. */
  current(): { command: Command; source: TeleopSource } | null {
    if (!this.enabled) return null;
    const { v, w } = this.limits;
    let axes: { forward: number; turn: number } | null = null;
    let source: TeleopSource | null = null;
    if (this.joystick) {
      axes = this.joystick;
      source = 'joystick';
    } else if (this.keys.size > 0) {
      axes = keysToAxes(this.keys);
      source = 'keyboard';
    } else {
      axes = this.gamepadAxes();
      source = axes ? 'gamepad' : null;
    }
    if (!axes || !source) return null;
    return { command: { v: round3(axes.forward * v), w: round3(axes.turn * w) }, source };
  }

  private lastTick = 0;

  private tick(): void {
    const now = performance.now();
    const wanted = this.current();
    if (wanted) {
      // Throttle event-driven ticks (key presses, joystick moves) to the send rate.
      if (this.active && now - this.lastTick < 1000 / SEND_HZ - 5 && wanted.source === this.lastSource) {
        this.options.onChange?.(wanted.command, wanted.source);
        return;
      }
      this.lastTick = now;
      this.active = true;
      this.lastSource = wanted.source;
      if (this.options.send(wanted.command) === 'offline') {
        this.interrupt();
        return;
      }
      this.options.onChange?.(wanted.command, wanted.source);
    } else if (this.active) {
      this.active = false;
      this.lastSource = null;
      this.options.send({ v: 0, w: 0 });
      this.options.onChange?.(null, null);
    }
  }
}

function round3(x: number): number {
  return Math.round(x * 1000) / 1000 + 0; // + 0 turns -0 into 0
}

/** The on-screen joystick: a round pad whose knob follows the pointer while pressed. */
export function mountJoystick(pad: HTMLElement, knob: HTMLElement, controller: TeleopController): void {
  let pointer: number | null = null;
  const update = (e: PointerEvent) => {
    const rect = pad.getBoundingClientRect();
    const radius = rect.width / 2;
    const dx = e.clientX - (rect.left + radius);
    const dy = e.clientY - (rect.top + rect.height / 2);
    const axes = padToAxes(dx, dy, radius * 0.8);
    knob.style.transform = `translate(${-axes.turn * radius * 0.8}px, ${-axes.forward * radius * 0.8}px)`;
    controller.setJoystick(axes);
  };
  const release = (e: PointerEvent) => {
    if (pointer !== e.pointerId) return;
    pointer = null;
    knob.style.transform = '';
    pad.classList.remove('active');
    controller.setJoystick(null);
  };
  pad.addEventListener('pointerdown', (e) => {
    if (pointer !== null) return;
    pointer = e.pointerId;
    pad.setPointerCapture(e.pointerId);
    pad.classList.add('active');
    e.preventDefault();
    update(e);
  });
  pad.addEventListener('pointermove', (e) => {
    if (pointer === e.pointerId) update(e);
  });
  pad.addEventListener('pointerup', release);
  pad.addEventListener('pointercancel', release);
  pad.addEventListener('lostpointercapture', release);
}
