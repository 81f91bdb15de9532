// The UAV colours of the CLI's pictures (src/render/canvas.cpp, uav_colour): ten colours, in order,
// then darker rounds of the same ten (x0.6 for the 2nd, 4th, ... round; x0.8 for the 3rd, 5th, ...).
export const PALETTE: ReadonlyArray<readonly [number, number, number]> = [
  [0.12, 0.47, 0.71],
  [1.0, 0.5, 0.05],
  [0.17, 0.63, 0.17],
  [0.84, 0.15, 0.16],
  [0.58, 0.4, 0.74],
  [0.55, 0.34, 0.29],
  [0.89, 0.47, 0.76],
  [0.5, 0.5, 0.5],
  [0.74, 0.74, 0.13],
  [0.09, 0.75, 0.81],
];

/** The colour of the i-th UAV (0-based) as CSS #rrggbb, as the CLI draws it. */
export function uavColour(i: number): string {
  const base = PALETTE[((i % 10) + 10) % 10];
  const f = i < 10 ? 1 : Math.floor(i / 10) % 2 === 1 ? 0.6 : 0.8;
  const hex = (v: number) =>
    Math.round(Math.min(1, Math.max(0, v * f)) * 255)
      .toString(16)
      .padStart(2, '0');
  return `#${hex(base[0])}${hex(base[1])}${hex(base[2])}`;
}
