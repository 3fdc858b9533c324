// Decoding the camera's JPEG frames without falling behind: one decode at a time; frames arriving
// meanwhile are not queued, only the newest is kept and decoded next (the ones it replaced are
// dropped and counted). Every decoded image is either handed over (the receiver closes the one it
// replaced) or, once disposed, closed at once, so no bitmap leaks. The decode and close functions
// are injected (createImageBitmap in the page, fakes in the unit test).

export interface FrameQueueOptions<T> {
  /** JPEG bytes -> a drawable image (createImageBitmap(new Blob([bytes], {type: 'image/jpeg'}))). */
  decode(bytes: Uint8Array): Promise<T>;
  /** A decoded frame for the receiver, which owns it from now on. */
  deliver(frame: T): void;
  /** Frees a frame nobody will draw (ImageBitmap.close). */
  discard(frame: T): void;
  /** A frame that did not decode. */
  failed?(error: unknown): void;
}

export class LatestFrameQueue<T> {
  decoded = 0;
  /** Frames never decoded because a newer one came while another was decoding. */
  dropped = 0;
  failures = 0;
  private busy = false;
  private pending: Uint8Array | null = null;
  private disposed = false;

  constructor(private readonly options: FrameQueueOptions<T>) {}

  /** Whether a decode is under way. */
  get decoding(): boolean {
    return this.busy;
  }

  /** A frame arrived. `bytes` may be a view into a buffer the caller no longer touches. */
  push(bytes: Uint8Array): void {
    if (this.disposed) return;
    if (this.busy) {
      if (this.pending) this.dropped++;
      this.pending = bytes;
      return;
    }
    void this.run(bytes);
  }

  /** Stops: nothing more is delivered; a decode under way is discarded when it ends. */
  dispose(): void {
    this.disposed = true;
    if (this.pending) this.dropped++;
    this.pending = null;
  }

  /** Starts again after dispose() (the panel shown again). */
  resume(): void {
    this.disposed = false;
  }

  private async run(bytes: Uint8Array): Promise<void> {
    this.busy = true;
    let next: Uint8Array | null = bytes;
    while (next) {
      try {
        const frame = await this.options.decode(next);
        if (this.disposed) {
          this.options.discard(frame);
        } else {
          this.decoded++;
          this.options.deliver(frame);
        }
      } catch (error) {
        this.failures++;
        this.options.failed?.(error);
      }
      next = this.disposed ? null : this.pending;
      this.pending = null;
    }
    this.busy = false;
  }
}
