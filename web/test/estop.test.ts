import { describe, expect, it } from 'vitest';
import { EstopChannel, EstopRefused, isEstopRefusal, STREAM_ACK_TIMEOUT_MS } from '../src/estop';
import type { EstopTransports } from '../src/estop';

/** Transports with a manual clock: what went on the stream and by REST. */
function transports(connected: boolean, restReply: (engaged: boolean) => Promise<boolean> = async (e) => e) {
  let now = 0;
  const timers = new Map<number, { at: number; fn: () => void }>();
  let nextId = 1;
  const sent: boolean[] = [];
  const rest: boolean[] = [];
  const t: EstopTransports = {
    streamSend: (engaged) => {
      if (!connected) return false;
      sent.push(engaged);
      return true;
    },
    rest: (engaged) => {
      rest.push(engaged);
      return restReply(engaged);
    },
    now: () => now,
    setTimeout: (fn, ms) => {
      timers.set(nextId, { at: now + ms, fn });
      return nextId++;
    },
    clearTimeout: (handle) => void timers.delete(handle as number),
  };
  const advance = (ms: number) => {
    now += ms;
    for (const [id, timer] of [...timers]) {
      if (timer.at <= now) {
        timers.delete(id);
        timer.fn();
      }
    }
  };
  return { t, sent, rest, advance, timers };
}

describe('the e-stop button', () => {
  it('goes on the stream when connected and is done at its acknowledgement', async () => {
    const x = transports(true);
    const channel = new EstopChannel(x.t);
    const done = channel.set(true);
    x.advance(12);
    expect(channel.onStreamAck(true)).toBe(true);
    expect(await done).toEqual({ engaged: true, via: 'stream', elapsedMs: 12 });
    expect(x.sent).toEqual([true]);
    expect(x.rest).toEqual([]);
    expect(x.timers.size).toBe(0);
  });

  it('uses REST when the stream is down', async () => {
    const x = transports(false);
    expect(await new EstopChannel(x.t).set(true)).toMatchObject({ engaged: true, via: 'rest' });
    expect(x.rest).toEqual([true]);
  });

  it('asks REST too when the stream does not answer in time, or closes', async () => {
    const x = transports(true);
    const channel = new EstopChannel(x.t);
    const late = channel.set(true);
    x.advance(STREAM_ACK_TIMEOUT_MS);
    expect(await late).toMatchObject({ engaged: true, via: 'rest' });
    // The stream's answer arriving afterwards belongs to nobody.
    expect(channel.onStreamAck(true)).toBe(false);
    const cut = channel.set(false);
    channel.onDisconnected();
    expect(await cut).toMatchObject({ engaged: false, via: 'rest' });
    expect(x.rest).toEqual([true, false]);
  });

  it('answers two clicks in order', async () => {
    const x = transports(true);
    const channel = new EstopChannel(x.t);
    const engage = channel.set(true);
    const release = channel.set(false);
    channel.onStreamAck(true);
    channel.onStreamAck(false);
    expect((await engage).engaged).toBe(true);
    expect((await release).engaged).toBe(false);
  });

  it('reports a refusal of the e-stop, and not a teleop refused because of it', async () => {
    const x = transports(true);
    const channel = new EstopChannel(x.t);
    const refused = channel.set(true);
    const engagedRefusal = 'the e-stop is engaged: teleop refused';
    expect(channel.onStreamError('estop_engaged', engagedRefusal, 'teleop')).toBe(false);
    expect(channel.onStreamError('forbidden', 'teleop needs the operator role', 'teleop')).toBe(false);
    expect(channel.onStreamError('malformed_json', 'the message is not valid JSON')).toBe(false);
    expect(channel.onStreamError('forbidden', 'this needs the operator role', 'estop')).toBe(true);
    await expect(refused).rejects.toBeInstanceOf(EstopRefused);
    expect(channel.waiting).toBe(false);
    // Nothing pending: no error is the e-stop's.
    expect(channel.onStreamError('forbidden', 'this needs the operator role', 'estop')).toBe(false);
  });

  it('knows an e-stop refusal by the request the server says it refuses', () => {
    expect(isEstopRefusal('estop')).toBe(true);
    expect(isEstopRefusal('teleop')).toBe(false);
    expect(isEstopRefusal(undefined)).toBe(false);
  });
});
