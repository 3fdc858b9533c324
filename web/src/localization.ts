// Localization as the robot reports it (`localization` of GET /api/v1/robot and the `status`
// topic): the method with its detail, the converged flag, the estimators an operator may switch
// to, and what the refusals of global localization and the estimator switch mean. Pure, unit-tested.

import { ApiError, errorText } from './apierror';

/** The estimators of PUT /api/v1/localization/method. */
export const ESTIMATORS = [
  { name: 'ekf', label: 'EKF' },
  { name: 'particle_filter', label: 'Particle filter' },
  { name: 'odometry', label: 'Odometry only' },
] as const;

export type EstimatorName = (typeof ESTIMATORS)[number]['name'];

/** The method families `/robot` reports; slam while mapping. */
export type MethodFamily = EstimatorName | 'slam';

export interface LocalizationMethod {
  /** As reported, e.g. "ekf(odometry+compass+lines+bearing)". */
  raw: string;
  /** The family the name starts with, or null for a name this dashboard does not know. */
  family: MethodFamily | null;
  /** What follows the family (the parenthesised detail without its parentheses), or null. */
  detail: string | null;
}

const FAMILIES: readonly MethodFamily[] = ['particle_filter', 'ekf', 'slam', 'odometry'];

/** Splits "ekf(odometry+compass)" / "particle_filter (2000 particles)" / "odometry" into family and detail. */
export function parseMethod(method: string | null | undefined): LocalizationMethod | null {
  if (typeof method !== 'string' || method.trim() === '') return null;
  const raw = method.trim();
  const family = FAMILIES.find((f) => raw === f || raw.startsWith(`${f}(`) || raw.startsWith(`${f} `)) ?? null;
  let detail: string | null = null;
  const rest = family ? raw.slice(family.length).trim() : '';
  if (rest) detail = rest.startsWith('(') && rest.endsWith(')') ? rest.slice(1, -1).trim() : rest;
  return { raw, family, detail: detail || null };
}

const FAMILY_LABELS: Record<MethodFamily, string> = {
  ekf: 'EKF',
  particle_filter: 'particle filter',
  slam: 'SLAM (mapping)',
  odometry: 'odometry',
};

/** Short label of a family ("EKF", "particle filter"), or the raw name. */
export function methodLabel(method: LocalizationMethod | null): string {
  if (!method) return '–';
  return method.family ? FAMILY_LABELS[method.family] : method.raw;
}

/** The estimator select's value for a reported method (slam and unknown names have none). */
export function estimatorOf(method: LocalizationMethod | null): EstimatorName | null {
  const f = method?.family;
  return f === 'ekf' || f === 'particle_filter' || f === 'odometry' ? f : null;
}

/** The `localization` object of /robot, validated. */
export interface LocalizationStatus {
  method: LocalizationMethod | null;
  cov: number[] | null;
  /** Absent on servers that do not report it. */
  converged: boolean | null;
}

export function parseLocalization(value: unknown): LocalizationStatus {
  const v = (value && typeof value === 'object' ? value : {}) as Record<string, unknown>;
  const cov = Array.isArray(v.cov) && v.cov.length === 9 && v.cov.every((x) => typeof x === 'number') ? (v.cov as number[]) : null;
  return {
    method: parseMethod(typeof v.method === 'string' ? v.method : null),
    cov,
    converged: typeof v.converged === 'boolean' ? v.converged : null,
  };
}

/** The message shown for a refused POST /localization/global or PUT /localization/method. */
export function localizationErrorText(error: unknown, what: 'global' | 'method'): string {
  if (error instanceof ApiError) {
    switch (error.code) {
      case 'no_map':
        return 'There is no map to localize on: activate or build one first (no_map).';
      case 'mapping_active':
        return what === 'global'
          ? 'Mapping is running: SLAM localizes the robot until mapping stops (mapping_active).'
          : 'Mapping is running: the estimator cannot be switched until mapping stops (mapping_active).';
      case 'forbidden':
        return 'This token may not change localization (the operator role is needed).';
      case 'estop_engaged':
        return 'The e-stop is engaged: release it first.';
      default:
        if (error.status === 404 && error.code === 'not_found') {
          return what === 'global' ? 'This server has no global localization.' : 'This server cannot switch the estimator.';
        }
        return error.describe();
    }
  }
  return errorText(error);
}

/** A method's detail as pieces that end at a '+' or ',' (where a narrow panel may break the line). */
export function detailPieces(detail: string): string[] {
  return detail.split(/(?<=[+,])/);
}
