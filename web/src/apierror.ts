// ApiError, what a failed REST call throws, in a module of its own: sweeps.ts explains refusals
// with it while api.ts takes the sweep bodies from sweeps.ts, so with the error in api.ts the two
// imported each other.

export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly code: string,
    message: string,
  ) {
    super(message);
  }

  /** "message (code)" for the UI. */
  describe(): string {
    return this.code && this.code !== 'network_error' ? `${this.message} (${this.code})` : this.message;
  }
}

/** A thrown value as text for the UI (an ApiError with its code). */
export function errorText(error: unknown): string {
  if (error instanceof ApiError) return error.describe();
  if (error instanceof Error) return error.message;
  return String(error);
}
