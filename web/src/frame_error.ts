// FrameError, what the binary and JSON frame decoders throw, in a module of its own: frames.ts
// dispatches to the decoders of tiles.ts, costmap.ts and particles.ts, which throw it too, so with
// the error in frames.ts they would import each other.

export class FrameError extends Error {}
