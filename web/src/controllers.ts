// The path-following controllers a goal may name, and which of them this robot takes. The server
// has no list of what it runs; the contract names lyapunov, dwa and vfh as taken, pure_pursuit and
// potential_field as refused on some robots (422 unsupported_controller). So every name is offered
// until the server refuses it; a refused one stays disabled, marked "not on this robot", until the
// server is another (a restart) or the page reloads. Pure, unit-tested.

export const CONTROLLERS = [
  { name: 'lyapunov', label: 'Lyapunov' },
  { name: 'dwa', label: 'DWA' },
  { name: 'vfh', label: 'VFH' },
  { name: 'pure_pursuit', label: 'Pure pursuit' },
  { name: 'potential_field', label: 'Potential field' },
] as const;

export const DEFAULT_CONTROLLER = 'lyapunov';

export interface ControllerOption {
  name: string;
  label: string;
  /** False once the server refused it with 422 unsupported_controller. */
  available: boolean;
}

export class ControllerChoice {
  private readonly refused = new Set<string>();

  options(): ControllerOption[] {
    return CONTROLLERS.map((c) => ({
      name: c.name,
      label: this.refused.has(c.name) ? `${c.label} (not on this robot)` : c.label,
      available: !this.refused.has(c.name),
    }));
  }

  /** The server answered 422 unsupported_controller for `name`. */
  refuse(name: string): void {
    if (name !== DEFAULT_CONTROLLER) this.refused.add(name);
  }

  isAvailable(name: string): boolean {
    return !this.refused.has(name);
  }

  /** `wanted` when it is offered, else the default. */
  pick(wanted: string): string {
    return CONTROLLERS.some((c) => c.name === wanted) && this.isAvailable(wanted) ? wanted : DEFAULT_CONTROLLER;
  }

  /** Another server (a restart): what the old one refused says nothing about it. */
  reset(): void {
    this.refused.clear();
  }
}
