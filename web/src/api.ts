// The server's API (docs/api.md), the only way the app reaches data. Every failure becomes an
// ApiError carrying the server's {"error": {"field", "message"}} so the UI can show it in words,
// next to the field it names.

export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly field: string,
    message: string,
  ) {
    super(message);
  }
}

export const API = '/api/v1';

async function send(method: string, path: string, body?: unknown): Promise<Response> {
  let res: Response;
  try {
    res = await fetch(API + path, {
      method,
      headers: body === undefined ? {} : { 'Content-Type': 'application/json' },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
  } catch {
    throw new ApiError(0, '', 'The server cannot be reached. Is `uavcover serve` running?');
  }
  return res;
}

function failure(res: Response, json: unknown): ApiError {
  const err = (json as { error?: { field?: string; message?: string } } | undefined)?.error;
  return new ApiError(res.status, err?.field ?? '', err?.message ?? `HTTP ${res.status}`);
}

async function request<T>(method: string, path: string, body?: unknown): Promise<T> {
  const res = await send(method, path, body);
  if (res.status === 204) return undefined as T;
  const text = await res.text();
  let json: unknown = undefined;
  try {
    json = text ? JSON.parse(text) : undefined;
  } catch {
    /* not JSON: reported below */
  }
  if (!res.ok) throw failure(res, json);
  return json as T;
}

/** A GET's body as bytes, unparsed (large files parsed off the main thread: plan-source.ts). */
async function bytes(path: string): Promise<ArrayBuffer> {
  const res = await send('GET', path);
  if (res.ok) return res.arrayBuffer();
  let json: unknown = undefined;
  try {
    json = await res.json();
  } catch {
    /* not JSON */
  }
  throw failure(res, json);
}

/** A multipart upload (the importer's file, the photos' heads) -> the JSON answer. */
async function postForm<T>(path: string, form: FormData): Promise<T> {
  let res: Response;
  try {
    res = await fetch(API + path, { method: 'POST', body: form });
  } catch {
    throw new ApiError(0, '', 'The server cannot be reached. Is `uavcover serve` running?');
  }
  const text = await res.text();
  let json: unknown = undefined;
  try {
    json = text ? JSON.parse(text) : undefined;
  } catch {
    /* not JSON: reported below */
  }
  if (!res.ok) throw failure(res, json);
  return json as T;
}

/** POST /missions/import (docs/import.md): the file as a multipart upload -> the mission skeleton. */
async function importFile<T>(file: Blob, name: string, options?: Record<string, unknown>): Promise<T> {
  const form = new FormData();
  form.append('file', file, name);
  if (options) form.append('options', JSON.stringify(options));
  return postForm<T>('/missions/import', form);
}

export const api = {
  importFile,
  postForm,
  get: <T>(path: string) => request<T>('GET', path),
  bytes,
  post: <T>(path: string, body?: unknown) => request<T>('POST', path, body ?? {}),
  put: <T>(path: string, body: unknown) => request<T>('PUT', path, body),
  del: <T>(path: string) => request<T>('DELETE', path),
};
