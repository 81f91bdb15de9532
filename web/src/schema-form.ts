// Forms generated from a planner's parameter schema (GET /api/v1/planners): one input per parameter,
// typed and bounded by the schema. The parsing is pure (unit-tested); renderSchemaForm builds the DOM.

export interface ParamSchema {
  name: string;
  type?: string;
  default?: unknown;
  minimum?: number;
  maximum?: number;
  description?: string;
  enum?: unknown[];
}

export interface PlannerSchema {
  name?: string;
  params?: ParamSchema[];
  /** JSON-Schema style, accepted too */
  properties?: Record<string, Omit<ParamSchema, 'name'>>;
}

export type FieldKind = 'integer' | 'number' | 'boolean' | 'enum' | 'string';

export interface FormField {
  name: string;
  kind: FieldKind;
  label: string;
  description: string;
  min?: number;
  max?: number;
  default: unknown;
  options?: unknown[];
}

export function fieldsFromSchema(schema: PlannerSchema | null | undefined): FormField[] {
  if (!schema) return [];
  const params: ParamSchema[] = Array.isArray(schema.params)
    ? schema.params
    : Object.entries(schema.properties ?? {}).map(([name, p]) => ({ ...p, name }));
  return params
    .filter((p) => p && typeof p.name === 'string')
    .map((p) => {
      const kind: FieldKind = Array.isArray(p.enum)
        ? 'enum'
        : p.type === 'integer' || p.type === 'number' || p.type === 'boolean'
          ? p.type
          : 'string';
      const f: FormField = {
        name: p.name,
        kind,
        label: p.name.replace(/_/g, ' '),
        description: p.description ?? '',
        default: p.default ?? null,
      };
      if (typeof p.minimum === 'number') f.min = p.minimum;
      if (typeof p.maximum === 'number') f.max = p.maximum;
      if (kind === 'enum') f.options = p.enum;
      return f;
    });
}

export interface Parsed {
  /** the value for planner_params; undefined = leave it out (the planner's default) */
  value: unknown;
  /** a message in words when the input is not acceptable */
  error?: string;
}

/** Parse what the operator typed (a string, or a boolean for check boxes) into a parameter value. */
export function parseField(f: FormField, raw: string | boolean): Parsed {
  if (f.kind === 'boolean') {
    if (typeof raw === 'boolean') return { value: raw };
    if (raw === 'true' || raw === 'false') return { value: raw === 'true' };
    return raw === '' ? { value: undefined } : { value: undefined, error: 'must be true or false' };
  }
  const s = String(raw).trim();
  if (s === '') return { value: undefined };
  if (f.kind === 'enum') {
    const opt = (f.options ?? []).find((o) => String(o) === s);
    return opt === undefined ? { value: undefined, error: `must be one of ${(f.options ?? []).join(', ')}` } : { value: opt };
  }
  if (f.kind === 'string') return { value: s };
  const x = Number(s);
  if (!Number.isFinite(x)) return { value: undefined, error: 'must be a number' };
  if (f.kind === 'integer' && !Number.isInteger(x)) return { value: x, error: 'must be a whole number' };
  if (f.min !== undefined && x < f.min) return { value: x, error: `must be at least ${f.min}` };
  if (f.max !== undefined && x > f.max) return { value: x, error: `must be at most ${f.max}` };
  return { value: x };
}

/** the text an input shows for a value ('' for absent/null) */
export function displayValue(value: unknown): string {
  return value === undefined || value === null ? '' : String(value);
}

/** the parameters with every default filled in (null defaults are left out) */
export function defaultParams(fields: FormField[]): Record<string, unknown> {
  const out: Record<string, unknown> = {};
  for (const f of fields) if (f.default !== null && f.default !== undefined) out[f.name] = f.default;
  return out;
}

/**
 * Keep only the parameters the schema knows and that differ from the default; unknown names are
 * dropped when the planner changes (they would be refused).
 */
export function paramsForSchema(fields: FormField[], values: Record<string, unknown>): Record<string, unknown> {
  const out: Record<string, unknown> = {};
  for (const f of fields) {
    const v = values[f.name];
    if (v !== undefined && v !== null && v !== f.default) out[f.name] = v;
  }
  return out;
}

/**
 * Build the form in `container`: one labelled input per field, named data-param=NAME, with a slot
 * for errors (data-field="planner_params.NAME"). `onChange` gets the new parameter object.
 */
export function renderSchemaForm(
  container: HTMLElement,
  fields: FormField[],
  values: Record<string, unknown>,
  onChange: (params: Record<string, unknown>, name: string, error?: string) => void,
): void {
  container.replaceChildren();
  if (fields.length === 0) {
    const p = document.createElement('p');
    p.className = 'muted define-small';
    p.textContent = 'This planner has no parameters.';
    container.appendChild(p);
    return;
  }
  const current: Record<string, unknown> = { ...values };
  for (const f of fields) {
    const row = document.createElement('label');
    row.className = 'define-param';
    row.dataset.anchor = `planner_params.${f.name}`;
    row.title = f.description;
    const name = document.createElement('span');
    name.textContent = f.label;
    row.appendChild(name);
    let input: HTMLInputElement | HTMLSelectElement;
    if (f.kind === 'boolean') {
      const cb = document.createElement('input');
      cb.type = 'checkbox';
      cb.checked = Boolean(current[f.name] ?? f.default);
      input = cb;
    } else if (f.kind === 'enum') {
      const sel = document.createElement('select');
      for (const o of f.options ?? []) {
        const opt = document.createElement('option');
        opt.value = String(o);
        opt.textContent = String(o);
        sel.appendChild(opt);
      }
      sel.value = displayValue(current[f.name] ?? f.default);
      input = sel;
    } else {
      const inp = document.createElement('input');
      inp.type = f.kind === 'string' ? 'text' : 'number';
      if (f.kind === 'integer') inp.step = '1';
      if (f.kind === 'number') inp.step = 'any';
      if (f.min !== undefined) inp.min = String(f.min);
      if (f.max !== undefined) inp.max = String(f.max);
      inp.placeholder = f.default === null ? 'automatic' : `default ${displayValue(f.default)}`;
      inp.value = displayValue(current[f.name]);
      input = inp;
    }
    input.dataset.param = f.name;
    input.addEventListener('change', () => {
      const raw = input instanceof HTMLInputElement && input.type === 'checkbox' ? input.checked : input.value;
      const parsed = parseField(f, raw);
      if (parsed.value === undefined) delete current[f.name];
      else current[f.name] = parsed.value;
      onChange({ ...current }, f.name, parsed.error);
    });
    row.appendChild(input);
    container.appendChild(row);
  }
}
