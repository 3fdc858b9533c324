// A periodic REST refresh that can also be asked to run at once (after a refusal, say) without
// ever flooding the server: one request in flight at a time, runs at most once a period on their
// own, asked-for runs at most once per minGapMs, and a reply that brought the state some other way
// (a POST answering with the new state) postpones the next run by a whole period. Timers are
// injected so the rules are unit-tested without a browser.

export interface PollTimers {
  setTimeout(fn: () => void, ms: number): unknown;
  clearTimeout(handle: unknown): void;
  now(): number;
}

const browserTimers: PollTimers = {
  setTimeout: (fn, ms) => globalThis.setTimeout(fn, ms),
  clearTimeout: (handle) => globalThis.clearTimeout(handle as ReturnType<typeof setTimeout>),
  now: () => performance.now(),
};

export interface PollerOptions {
  /** Between the starts of two periodic runs. */
  periodMs: number;
  /** Between the start of any run and a run asked for with poke(). */
  minGapMs: number;
}

export class Poller {
  /** Runs started (for tests and the page's hooks). */
  runs = 0;
  private timer: unknown = null;
  private running = false;
  private started = false;
  /** A poke came while a run was in flight: run again once it ends. */
  private pokedWhileRunning = false;
  private lastStart = Number.NEGATIVE_INFINITY;
  /** Bumped by stop(): a run that ends after it schedules nothing. */
  private generation = 0;

  constructor(
    private readonly task: () => Promise<void>,
    private readonly options: PollerOptions,
    private readonly timers: PollTimers = browserTimers,
  ) {}

  get active(): boolean {
    return this.started;
  }

  /** Starts polling with a run now (a no-op when already started). */
  start(): void {
    if (this.started) return;
    this.started = true;
    this.schedule(0);
  }

  stop(): void {
    this.started = false;
    this.pokedWhileRunning = false;
    this.generation++;
    this.clear();
  }

  /** Asks for a run as soon as the minimum gap allows (coalesced with one in flight). */
  poke(): void {
    if (!this.started) return;
    if (this.running) {
      this.pokedWhileRunning = true;
      return;
    }
    this.schedule(Math.max(0, this.lastStart + this.options.minGapMs - this.timers.now()));
  }

  /** The state arrived another way just now: the next periodic run is a whole period away. */
  fresh(): void {
    if (!this.started) return;
    this.lastStart = this.timers.now();
    if (!this.running) this.schedule(this.options.periodMs);
  }

  private schedule(delayMs: number): void {
    this.clear();
    this.timer = this.timers.setTimeout(() => {
      this.timer = null;
      void this.run();
    }, delayMs);
  }

  private clear(): void {
    if (this.timer !== null) this.timers.clearTimeout(this.timer);
    this.timer = null;
  }

  private async run(): Promise<void> {
    if (!this.started || this.running) return;
    const generation = this.generation;
    this.running = true;
    this.lastStart = this.timers.now();
    this.runs++;
    try {
      await this.task();
    } catch {
      // The task reports its own errors; polling goes on.
    } finally {
      this.running = false;
    }
    if (generation !== this.generation || !this.started) return;
    const now = this.timers.now();
    if (this.pokedWhileRunning) {
      this.pokedWhileRunning = false;
      this.schedule(Math.max(0, this.lastStart + this.options.minGapMs - now));
    } else {
      // From this run's start, or from a fresh() that came during it.
      this.schedule(Math.max(0, this.lastStart + this.options.periodMs - now));
    }
  }
}
