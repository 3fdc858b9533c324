// The e-stop button's request: on the stream when it is connected (`{"op":"estop","engaged"}`,
// carried out as it is read and answered ahead of every queued frame, docs/api.md), else by REST
// (POST /api/v1/estop). A stream request not acknowledged within STREAM_ACK_TIMEOUT_MS, or whose
// stream closes first, is sent again by REST: setting the e-stop twice to the same state changes
// nothing, and a stop must not wait for a link that may be the reason for it. Transports and
// timers are injected (unit-tested); main.ts shows the result.

/** A stream e-stop is answered in a round trip plus a commit; past this REST is asked as well. */
export const STREAM_ACK_TIMEOUT_MS = 1000;

export type EstopVia = 'stream' | 'rest';

export interface EstopAck {
  engaged: boolean;
  via: EstopVia;
  /** From the click to the acknowledgement. */
  elapsedMs: number;
}

export interface EstopTransports {
  /** Sends `{"op":"estop","engaged"}` on the stream; false when it is not connected. */
  streamSend(engaged: boolean): boolean;
  /** POST /api/v1/estop; resolves with the state the server reports, rejects with its refusal. */
  rest(engaged: boolean): Promise<boolean>;
  now(): number;
  setTimeout(fn: () => void, ms: number): unknown;
  clearTimeout(handle: unknown): void;
}

/** A stream error that answers an e-stop request (not a teleop refused because of the e-stop). */
export class EstopRefused extends Error {
  constructor(
    readonly code: string,
    message: string,
  ) {
    super(message);
  }
}

/**
 * Whether a stream `{"op":"error"}` answers the pending e-stop: the server names the request an
 * error refuses (`request_op`). An `estop_engaged` that refuses a teleop is about the e-stop but
 * no answer to it.
 */
export function isEstopRefusal(requestOp: string | undefined): boolean {
  return requestOp === 'estop';
}

interface Pending {
  engaged: boolean;
  startedAt: number;
  timer: unknown;
  resolve(ack: EstopAck): void;
  reject(error: unknown): void;
}

export class EstopChannel {
  /** Stream requests waiting for their answer, oldest first: the server answers them in order. */
  private readonly pending: Pending[] = [];

  constructor(private readonly transports: EstopTransports) {}

  /** An e-stop request is waiting for the stream's answer. */
  get waiting(): boolean {
    return this.pending.length > 0;
  }

  /** Engages or releases the e-stop; resolves once acknowledged, rejects with the refusal. */
  set(engaged: boolean): Promise<EstopAck> {
    const startedAt = this.transports.now();
    if (!this.transports.streamSend(engaged)) return this.viaRest(engaged, startedAt);
    return new Promise<EstopAck>((resolve, reject) => {
      const p: Pending = { engaged, startedAt, timer: null, resolve, reject };
      p.timer = this.transports.setTimeout(() => this.fallBack(p), STREAM_ACK_TIMEOUT_MS);
      this.pending.push(p);
    });
  }

  /** The stream's `{"op":"estop","engaged"}`: the oldest pending request is done. */
  onStreamAck(engaged: boolean): boolean {
    const p = this.take(this.pending[0]);
    if (!p) return false;
    p.resolve({ engaged, via: 'stream', elapsedMs: this.transports.now() - p.startedAt });
    return true;
  }

  /** A stream error; true when it was a pending e-stop's refusal (and is reported by it). */
  onStreamError(code: string, message: string, requestOp?: string): boolean {
    if (!this.pending.length || !isEstopRefusal(requestOp)) return false;
    this.take(this.pending[0])!.reject(new EstopRefused(code, message));
    return true;
  }

  /** The stream closed: the requests it carried may be lost; REST is asked at once. */
  onDisconnected(): void {
    for (const p of [...this.pending]) this.fallBack(p);
  }

  private fallBack(p: Pending): void {
    if (this.take(p)) this.viaRest(p.engaged, p.startedAt).then(p.resolve, p.reject);
  }

  /** Removes `p` from the waiting list (and its timer); null when it was not waiting any more. */
  private take(p: Pending | undefined): Pending | null {
    const i = p ? this.pending.indexOf(p) : -1;
    if (i < 0) return null;
    this.pending.splice(i, 1);
    this.transports.clearTimeout(p!.timer);
    return p!;
  }

  private async viaRest(engaged: boolean, startedAt: number): Promise<EstopAck> {
    const state = await this.transports.rest(engaged);
    return { engaged: state, via: 'rest', elapsedMs: this.transports.now() - startedAt };
  }
}
