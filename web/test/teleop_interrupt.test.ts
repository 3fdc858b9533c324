import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { TeleopController } from '../src/teleop';
import type { Command, SendResult } from '../src/teleop';

/** The window's listeners, so the test can press keys. */
const listeners = new Map<string, (e: unknown) => void>();

const key = (type: 'keydown' | 'keyup', name: string, repeat = false) =>
  listeners.get(type)!({ key: name, repeat, ctrlKey: false, metaKey: false, altKey: false, target: null, preventDefault() {} });

beforeEach(() => {
  listeners.clear();
  vi.useFakeTimers({ toFake: ['setInterval', 'clearInterval', 'performance'] });
  vi.stubGlobal('window', {
    addEventListener: (type: string, fn: (e: unknown) => void) => listeners.set(type, fn),
    removeEventListener: () => {},
    setInterval: (fn: () => void, ms: number) => setInterval(fn, ms),
    clearInterval: (id: number) => clearInterval(id),
  });
  vi.stubGlobal('document', { addEventListener: () => {}, hidden: false });
  vi.stubGlobal('navigator', {});
  vi.stubGlobal('HTMLElement', class {});
});

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

function controller(link: { up: boolean }) {
  const sent: Command[] = [];
  const c = new TeleopController({
    send: (command): SendResult => {
      if (!link.up) return 'offline';
      sent.push(command);
      return 'sent';
    },
  });
  return { c, sent };
}

describe('teleop when the link goes down', () => {
  it('drops the command, lets the key go, and drives again only after a new press', () => {
    const link = { up: true };
    const { c, sent } = controller(link);
    key('keydown', 'w');
    expect(sent.at(-1)).toEqual({ v: 0.5, w: 0 });
    link.up = false;
    vi.advanceTimersByTime(200);
    expect(c.interrupts).toBe(1);
    const before = sent.length;
    // The link is back; the key is still held (the browser repeats it): nothing is sent.
    link.up = true;
    key('keydown', 'w', true);
    vi.advanceTimersByTime(500);
    expect(sent.length).toBe(before);
    // Released and pressed again: driving.
    key('keyup', 'w');
    key('keydown', 'w');
    expect(sent.length).toBe(before + 1);
    expect(sent.at(-1)).toEqual({ v: 0.5, w: 0 });
    c.dispose();
  });

  it('holds a joystick still through an outage until it is let go', () => {
    const link = { up: true };
    const { c, sent } = controller(link);
    c.setJoystick({ forward: 1, turn: 0 });
    c.interrupt();
    const before = sent.length;
    c.setJoystick({ forward: 0.8, turn: 0 });
    vi.advanceTimersByTime(300);
    expect(sent.length).toBe(before);
    c.setJoystick(null);
    c.setJoystick({ forward: 0.8, turn: 0 });
    expect(sent.at(-1)).toEqual({ v: 0.4, w: 0 });
    c.dispose();
  });

  it('lets a joystick that was not held drive at its first drag after an outage', () => {
    const { c, sent } = controller({ up: true });
    c.interrupt();
    c.setJoystick({ forward: 1, turn: 0 });
    expect(sent.at(-1)).toEqual({ v: 0.5, w: 0 });
    c.dispose();
  });
});
