// A tiny impairing TCP proxy for the browser test: the dashboard is loaded through it so that the
// link between the browser and mobotd can be made slow or cut, as a remote operator's can be.
//
//   const proxy = await startLinkProxy({ port: mobotdPort });
//   page.goto(`${proxy.url}/?token=...`);   // REST and the stream go through the proxy
//   proxy.setDelay(150);                     // 150 ms added each way (so >= 300 ms round trip)
//   proxy.cut();                             // every connection destroyed, new ones refused
//   proxy.restore();                         // accepted again
//   proxy.closeStreams(4401, 'revoked');     // a WebSocket close frame "from the server"
//   await proxy.close();
//
// It listens on 127.0.0.1:0 and forwards bytes unchanged, each chunk held back `delayMs` in its
// direction (order kept). To forge a close frame it follows the server's side of each connection:
// an HTTP response "101 Switching Protocols" starts WebSocket frames, whose lengths say where each
// ends, so the close frame goes in between two frames and nothing the server sends after it is
// passed on.

import net from 'node:net';

/** Server-to-client WebSocket frames (RFC 6455 section 5.2: not masked), followed to their ends. */
class ServerFrames {
  constructor() {
    this.phase = 'http'; // 'http' until the response head ends, then 'ws' (upgraded) or 'plain'
    this.head = Buffer.alloc(0);
    this.header = Buffer.alloc(0); // the part of a frame header read so far
    this.left = 0; // payload bytes of the current frame still to pass
  }

  get upgraded() {
    return this.phase === 'ws';
  }

  /** Between two frames: a close frame may be written now. */
  get atBoundary() {
    return this.phase === 'ws' && this.left === 0 && this.header.length === 0;
  }

  /**
   * Splits `chunk` at frame boundaries: calls `piece(bytes, boundary)` for each part, `boundary`
   * true when a frame ends with it (or the HTTP head does).
   */
  split(chunk, piece) {
    let i = 0;
    if (this.phase === 'http') {
      this.head = Buffer.concat([this.head, chunk]);
      const end = this.head.indexOf('\r\n\r\n');
      if (end < 0) {
        if (this.head.length > 16384) this.phase = 'plain';
        piece(chunk, false);
        return;
      }
      this.phase = /^HTTP\/1\.1 101/.test(this.head.subarray(0, 16).toString('latin1')) ? 'ws' : 'plain';
      const headBytesInChunk = chunk.length - (this.head.length - (end + 4));
      this.head = Buffer.alloc(0);
      piece(chunk.subarray(0, headBytesInChunk), this.phase === 'ws');
      i = headBytesInChunk;
    }
    if (this.phase !== 'ws') {
      if (i < chunk.length) piece(chunk.subarray(i), false);
      return;
    }
    let start = i;
    while (i < chunk.length) {
      if (this.left > 0) {
        const take = Math.min(this.left, chunk.length - i);
        i += take;
        this.left -= take;
        if (this.left === 0) {
          piece(chunk.subarray(start, i), true);
          start = i;
        }
        continue;
      }
      this.header = Buffer.concat([this.header, chunk.subarray(i, i + 1)]);
      i++;
      const length = this.frameLength();
      if (length === null) continue;
      this.header = Buffer.alloc(0);
      this.left = length;
      if (length === 0) {
        piece(chunk.subarray(start, i), true);
        start = i;
      }
    }
    if (start < chunk.length) piece(chunk.subarray(start), false);
  }

  /** The payload length once the header read so far is whole; null while it is not. */
  frameLength() {
    const h = this.header;
    if (h.length < 2) return null;
    const short = h[1] & 0x7f;
    const masked = (h[1] & 0x80) !== 0;
    const size = 2 + (short === 126 ? 2 : short === 127 ? 8 : 0) + (masked ? 4 : 0);
    if (h.length < size) return null;
    if (short === 126) return h.readUInt16BE(2);
    if (short === 127) return Number(h.readBigUInt64BE(2));
    return short;
  }
}

/** A WebSocket close frame as a server sends it (unmasked). */
function closeFrame(code, reason) {
  const text = Buffer.from(reason, 'utf8').subarray(0, 123);
  const frame = Buffer.alloc(4 + text.length);
  frame[0] = 0x88; // FIN + close
  frame[1] = 2 + text.length;
  frame.writeUInt16BE(code, 2);
  text.copy(frame, 4);
  return frame;
}

/** Writes what is pushed to `to` after `delay()` ms, in order. */
function delayedPipe(to, delay) {
  const queue = [];
  let timer = null;
  let lastDue = 0;
  const pump = () => {
    timer = null;
    const now = Date.now();
    while (queue.length && queue[0].due <= now) {
      const { data } = queue.shift();
      if (!to.destroyed) to.write(data);
    }
    if (queue.length) timer = setTimeout(pump, queue[0].due - now);
  };
  return {
    push(data) {
      // A delay made shorter meanwhile must not overtake what is already waiting.
      lastDue = Math.max(Date.now() + delay(), lastDue);
      if (delay() === 0 && queue.length === 0) {
        if (!to.destroyed) to.write(data);
        return;
      }
      queue.push({ due: lastDue, data });
      if (!timer) timer = setTimeout(pump, Math.max(0, queue[0].due - Date.now()));
    },
    clear() {
      queue.length = 0;
      if (timer) clearTimeout(timer);
      timer = null;
    },
  };
}

/**
 * Starts the proxy in front of `host:port`. Resolves with its controls once it listens.
 * @param {{ port: number, host?: string, delayMs?: number }} options
 */
export async function startLinkProxy({ port, host = '127.0.0.1', delayMs = 0 }) {
  let delay = delayMs;
  let cut = false;
  const links = new Set();
  const stats = { accepted: 0, refused: 0, upgrades: 0, closeFramesSent: 0 };

  const server = net.createServer((client) => {
    if (cut) {
      stats.refused++;
      client.destroy();
      return;
    }
    stats.accepted++;
    client.setNoDelay(true);
    const upstream = net.connect({ host, port });
    upstream.setNoDelay(true);
    const frames = new ServerFrames();
    const toServer = delayedPipe(upstream, () => delay);
    // The server's bytes, split at frame ends, go through the delay; a close frame asked for is
    // written at the next frame end, in order with the rest.
    const toClient = delayedPipe(client, () => delay);
    const link = {
      client,
      upstream,
      frames,
      upgraded: false, // the server switched it to WebSocket (counted in stats.upgrades)
      closing: null, // {code, reason} once a close frame was asked for
      closed: false,
      destroy() {
        toServer.clear();
        toClient.clear();
        client.destroy();
        upstream.destroy();
        links.delete(link);
      },
      /** Ends the server's side with a close frame "from the server" at a frame boundary. */
      sendClose() {
        if (link.closed) return;
        link.closed = true;
        stats.closeFramesSent++;
        toClient.push(closeFrame(link.closing.code, link.closing.reason));
        upstream.destroy();
        // The browser answers with its own close frame; then the TCP connection goes.
        setTimeout(() => link.destroy(), delay + 500);
      },
    };
    links.add(link);
    client.on('data', (data) => {
      if (!link.closed) toServer.push(data);
    });
    upstream.on('data', (data) => {
      if (link.closed) return;
      frames.split(data, (bytes, boundary) => {
        if (link.closed) return;
        toClient.push(bytes);
        if (boundary && frames.upgraded && !link.upgraded) {
          link.upgraded = true;
          stats.upgrades++;
        }
        if (boundary && frames.upgraded && link.closing) link.sendClose();
      });
    });
    const end = () => link.destroy();
    client.on('error', end);
    upstream.on('error', end);
    client.on('close', end);
    upstream.on('close', () => {
      if (!link.closed) setTimeout(end, delay);
    });
  });

  await new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(0, '127.0.0.1', resolve);
  });
  const { port: proxyPort } = server.address();

  return {
    port: proxyPort,
    url: `http://127.0.0.1:${proxyPort}`,
    stats,
    /** Connections open now, and how many of them are WebSocket streams. */
    get connections() {
      return { open: links.size, streams: [...links].filter((l) => l.frames.upgraded && !l.closed).length };
    },
    /** Added to each direction from now on (ms). */
    setDelay(ms) {
      delay = ms;
    },
    /** Every connection destroyed at once (no FIN, no close frame), new ones refused. */
    cut() {
      cut = true;
      for (const link of [...links]) link.destroy();
    },
    /** New connections accepted again. */
    restore() {
      cut = false;
    },
    /** Each WebSocket stream gets a close frame with `code` and `reason`, as if from mobotd. */
    closeStreams(code, reason = '') {
      let count = 0;
      for (const link of links) {
        if (!link.frames.upgraded || link.closed) continue;
        link.closing = { code, reason };
        count++;
        if (link.frames.atBoundary) link.sendClose();
      }
      return count;
    },
    async close() {
      cut = true;
      for (const link of [...links]) link.destroy();
      await new Promise((resolve) => server.close(() => resolve()));
    },
  };
}
