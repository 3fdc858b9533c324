// Colours shared by more than one part of the map view; a layer's own colours live in its file.

import type { GoalStatus } from '../goals';

/** The canvas behind everything (also the hollow of the run trajectory's start marker). */
export const BACKGROUND = '#0b0f14';

/** Labels drawn on the map (scale bar, cursor readout). */
export const TEXT = 'rgba(226, 232, 240, 0.85)';

/** The dark outline under a mark that keeps it readable over the map and the scan. */
export const CASING = 'rgba(11, 15, 20, 0.8)';

/** Colour of a goal status (marker, badges). */
export const STATUS_COLORS: Record<GoalStatus, string> = {
  planning: '#fbbf24',
  active: '#38bdf8',
  succeeded: '#34d399',
  failed: '#f87171',
  canceled: '#94a3b8',
};
