// The CLI's palette (src/render/render.cpp uav_colour): ten colour-blind-distinguishable colours, then
// darker rounds (×0.8, ×0.6, ×0.8, …). Same colours on the map as in the CLI's pictures.
const BASE: [number, number, number][] = [
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

function hex(r: number, g: number, b: number): string {
  const c = (x: number) => Math.round(Math.min(1, Math.max(0, x)) * 255).toString(16).padStart(2, '0');
  return `#${c(r)}${c(g)}${c(b)}`;
}

/** the base palette as CSS hex colours */
export const PALETTE: string[] = BASE.map(([r, g, b]) => hex(r, g, b));

/** colour of the i-th UAV (0-based), as render.cpp's uav_colour */
export function uavColour(i: number): string {
  const [r, g, b] = BASE[((i % 10) + 10) % 10];
  if (i < 10) return hex(r, g, b);
  const f = Math.floor(i / 10) % 2 === 1 ? 0.6 : 0.8;
  return hex(r * f, g * f, b * f);
}

/** no-fly zones: red fill, dark red outline (render.cpp) */
export const NFZ_FILL = hex(0.85, 0.2, 0.2);
export const NFZ_STROKE = hex(0.7, 0.1, 0.1);

/** the area: light fill, dark grey outline (render.cpp) */
export const AREA_FILL = hex(0.95, 0.95, 0.93);
export const AREA_STROKE = hex(0.25, 0.25, 0.25);
