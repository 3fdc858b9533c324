import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { estimatorOf, localizationErrorText, methodLabel, parseLocalization, parseMethod } from '../src/localization';

describe('localization methods', () => {
  it('split family and parenthesised detail', () => {
    expect(parseMethod('ekf(odometry+compass+lines+bearing)')).toEqual({ raw: 'ekf(odometry+compass+lines+bearing)', family: 'ekf', detail: 'odometry+compass+lines+bearing' });
    expect(parseMethod('particle_filter (2000 particles)')).toMatchObject({ family: 'particle_filter', detail: '2000 particles' });
    expect(parseMethod('slam(graph)')).toMatchObject({ family: 'slam', detail: 'graph' });
    expect(parseMethod('odometry')).toMatchObject({ family: 'odometry', detail: null });
    expect(parseMethod('ukf')).toMatchObject({ family: null, detail: null });
    expect(parseMethod('')).toBeNull();
    expect(parseMethod(undefined)).toBeNull();
  });

  it('label families and map them to the estimator select', () => {
    expect(methodLabel(parseMethod('particle_filter'))).toBe('particle filter');
    expect(methodLabel(parseMethod('ukf'))).toBe('ukf');
    expect(estimatorOf(parseMethod('ekf(odometry)'))).toBe('ekf');
    expect(estimatorOf(parseMethod('slam'))).toBeNull();
    expect(estimatorOf(null)).toBeNull();
  });

  it('read the /robot localization object, converged only when reported', () => {
    const cov = [1, 0, 0, 0, 1, 0, 0, 0, 1];
    expect(parseLocalization({ method: 'particle_filter', cov, converged: false })).toMatchObject({ cov, converged: false, method: { family: 'particle_filter' } });
    expect(parseLocalization({ method: 'ekf', cov: [1, 2] })).toMatchObject({ cov: null, converged: null });
    expect(parseLocalization(undefined)).toEqual({ method: null, cov: null, converged: null });
  });

  it('explain refusals of global localization and the estimator switch', () => {
    expect(localizationErrorText(new ApiError(409, 'no_map', 'no map'), 'global')).toMatch(/no map to localize on/);
    expect(localizationErrorText(new ApiError(409, 'mapping_active', 'x'), 'global')).toMatch(/SLAM localizes/);
    expect(localizationErrorText(new ApiError(409, 'mapping_active', 'x'), 'method')).toMatch(/cannot be switched/);
    expect(localizationErrorText(new ApiError(404, 'not_found', 'x'), 'global')).toMatch(/no global localization/);
    expect(localizationErrorText(new ApiError(400, 'invalid_field', 'method must be one of ...'), 'method')).toBe('method must be one of ... (invalid_field)');
  });
});
