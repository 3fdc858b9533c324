import { describe, expect, it } from 'vitest';
import { LatestFrameQueue } from '../src/camera_frames';

/** A fake decoder whose decodes finish when the test says. */
function harness() {
  const waiting: { bytes: Uint8Array; resolve: (frame: { id: number; closed: boolean }) => void; reject: (e: unknown) => void }[] = [];
  const delivered: { id: number; closed: boolean }[] = [];
  const discarded: { id: number; closed: boolean }[] = [];
  const queue = new LatestFrameQueue<{ id: number; closed: boolean }>({
    decode: (bytes) => new Promise((resolve, reject) => waiting.push({ bytes, resolve, reject })),
    deliver: (frame) => delivered.push(frame),
    discard: (frame) => {
      frame.closed = true;
      discarded.push(frame);
    },
  });
  const finish = async (ok = true) => {
    const job = waiting.shift()!;
    if (ok) job.resolve({ id: job.bytes[0]!, closed: false });
    else job.reject(new Error('bad jpeg'));
    await new Promise((r) => setTimeout(r, 0));
  };
  return { queue, waiting, delivered, discarded, finish };
}

const frame = (id: number) => new Uint8Array([id, 0xff, 0xd8]);

describe('camera frame decoding', () => {
  it('decodes one at a time and keeps only the newest frame that came meanwhile', async () => {
    const h = harness();
    h.queue.push(frame(1));
    h.queue.push(frame(2));
    h.queue.push(frame(3));
    h.queue.push(frame(4));
    expect(h.waiting.length).toBe(1);
    expect(h.queue.decoding).toBe(true);
    await h.finish();
    // 2 and 3 were replaced by 4 while 1 decoded.
    expect(h.queue.dropped).toBe(2);
    expect(h.waiting.map((w) => w.bytes[0])).toEqual([4]);
    await h.finish();
    expect(h.delivered.map((f) => f.id)).toEqual([1, 4]);
    expect(h.queue.decoded).toBe(2);
    expect(h.queue.decoding).toBe(false);
    h.queue.push(frame(5));
    await h.finish();
    expect(h.delivered.map((f) => f.id)).toEqual([1, 4, 5]);
  });

  it('closes a frame decoded after dispose and decodes nothing more until resumed', async () => {
    const h = harness();
    h.queue.push(frame(1));
    h.queue.push(frame(2));
    h.queue.dispose();
    await h.finish();
    expect(h.delivered).toEqual([]);
    expect(h.discarded).toEqual([{ id: 1, closed: true }]);
    expect(h.waiting.length).toBe(0);
    h.queue.push(frame(3));
    expect(h.waiting.length).toBe(0);
    h.queue.resume();
    h.queue.push(frame(4));
    await h.finish();
    expect(h.delivered.map((f) => f.id)).toEqual([4]);
  });

  it('goes on after a frame that does not decode', async () => {
    const h = harness();
    h.queue.push(frame(1));
    h.queue.push(frame(2));
    await h.finish(false);
    expect(h.queue.failures).toBe(1);
    await h.finish();
    expect(h.delivered.map((f) => f.id)).toEqual([2]);
  });
});
