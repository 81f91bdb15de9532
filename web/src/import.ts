// Importing a file: a uavcover mission or an mCPP-optimized-DARP input is sent to the server as it is
// (the server detects the format); GeoJSON and KML give a draft mission (area and no-fly zones) that
// opens in the Define tab. Pure except kmlPolygons, which reads a parsed XML document.
import { draftFromPolygons, geojsonPolygons, type MissionDoc, type PolygonCoords, type Position, type Role } from './mission-doc.ts';

export type Imported =
  | { kind: 'mission'; body: unknown; format: 'uavcover' | 'mcpp' }
  | { kind: 'draft'; doc: MissionDoc; format: 'geojson' | 'kml' };

const GEOJSON_TYPES = new Set([
  'FeatureCollection',
  'Feature',
  'GeometryCollection',
  'Polygon',
  'MultiPolygon',
  'Point',
  'MultiPoint',
  'LineString',
  'MultiLineString',
]);

function baseName(file: string): string {
  return file.replace(/^.*[\\/]/, '').replace(/\.[^.]*$/, '') || 'Imported mission';
}

/** parse a coordinate list "lon,lat[,alt] lon,lat[,alt] …" */
export function kmlCoordinates(text: string): Position[] {
  const out: Position[] = [];
  for (const tuple of text.trim().split(/\s+/)) {
    const [x, y] = tuple.split(',').map(Number);
    if (Number.isFinite(x) && Number.isFinite(y)) out.push([x, y]);
  }
  return out;
}

/** the polygons of a KML document: outerBoundaryIs and innerBoundaryIs rings, roles from names */
export function kmlPolygons(xml: Document): { coords: PolygonCoords; role?: Role }[] {
  const out: { coords: PolygonCoords; role?: Role }[] = [];
  const byName = (el: Element, name: string) => Array.from(el.getElementsByTagNameNS('*', name));
  for (const poly of byName(xml.documentElement, 'Polygon')) {
    const ring = (b: Element) => kmlCoordinates(byName(b, 'coordinates')[0]?.textContent ?? '');
    const outer = byName(poly, 'outerBoundaryIs').map(ring)[0];
    if (!outer || outer.length < 3) continue;
    const holes = byName(poly, 'innerBoundaryIs').map(ring).filter((r) => r.length >= 3);
    let role: Role;
    for (let p: Element | null = poly.parentElement; p; p = p.parentElement) {
      if (p.localName !== 'Placemark') continue;
      const name = Array.from(p.children).find((c) => c.localName === 'name')?.textContent ?? '';
      if (/no[\s_-]*fly|\bnfz\b|obstacle/i.test(name)) role = 'nfz';
      break;
    }
    out.push({ coords: [outer, ...holes], role });
  }
  return out;
}

/**
 * The name a KML gives itself: the Document's <name> (or a lone Folder's), else the name of the first
 * Placemark holding a Polygon that is not a no-fly zone; null when there is none.
 */
export function kmlName(xml: Document): string | null {
  const text = (e: Element | undefined) => e?.textContent?.trim() || null;
  const childName = (e: Element) => Array.from(e.children).find((c) => c.localName === 'name');
  const root = xml.documentElement;
  for (const tag of ['Document', 'Folder']) {
    const holder = root.localName === tag ? root : Array.from(root.getElementsByTagNameNS('*', tag))[0];
    const n = holder ? text(childName(holder)) : null;
    if (n) return n;
  }
  for (const pm of Array.from(root.getElementsByTagNameNS('*', 'Placemark'))) {
    if (pm.getElementsByTagNameNS('*', 'Polygon').length === 0) continue;
    const n = text(childName(pm));
    if (n && !/no[\s_-]*fly|\bnfz\b|obstacle/i.test(n)) return n;
  }
  return null;
}

/**
 * Read a file's text. `parseXml` turns KML text into a Document (DOMParser in the browser).
 * Throws an Error whose message says in words what is wrong.
 */
export function readImport(text: string, fileName: string, parseXml?: (s: string) => Document): Imported {
  const name = baseName(fileName);
  const trimmed = text.trimStart();
  if (trimmed.startsWith('<')) {
    if (!parseXml) throw new Error('KML cannot be read here');
    const xml = parseXml(text);
    if (xml.getElementsByTagName('parsererror').length > 0) throw new Error(`${fileName}: not well-formed XML`);
    const polys = kmlPolygons(xml);
    if (polys.length === 0) throw new Error(`${fileName}: the KML has no Polygon`);
    return { kind: 'draft', doc: draftFromPolygons(kmlName(xml) ?? name, polys), format: 'kml' };
  }
  let json: unknown;
  try {
    json = JSON.parse(text);
  } catch (e) {
    throw new Error(`${fileName}: neither JSON nor KML (${(e as Error).message})`);
  }
  if (!json || typeof json !== 'object' || Array.isArray(json)) throw new Error(`${fileName}: a JSON object is expected`);
  const o = json as Record<string, unknown>;
  if ('droneNo' in o || ('polygon' in o && !('area' in o))) return { kind: 'mission', body: o, format: 'mcpp' };
  if ('area' in o) return { kind: 'mission', body: o, format: 'uavcover' };
  if (typeof o.type === 'string' && GEOJSON_TYPES.has(o.type)) {
    const polys = geojsonPolygons(o);
    if (polys.length === 0) throw new Error(`${fileName}: the GeoJSON has no Polygon or MultiPolygon`);
    // a name given in the file: {"name"} on a FeatureCollection, properties.name on a lone Feature
    const props = o.properties as Record<string, unknown> | undefined;
    const given = o.type === 'Feature' && props && typeof props.name === 'string' ? props.name : o.name;
    const title = typeof given === 'string' && given.trim() ? given.trim() : name;
    return { kind: 'draft', doc: draftFromPolygons(title, polys), format: 'geojson' };
  }
  throw new Error(
    `${fileName}: not a uavcover mission ("area"), an mCPP-optimized-DARP input ("droneNo"/"polygon"), GeoJSON or KML`,
  );
}
