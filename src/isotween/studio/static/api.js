// The studio's HTTP JSON API: every call carries the session token.
const token = new URLSearchParams(location.search).get("token") || "";

export class ApiError extends Error {}

async function answer(response) {
  const type = response.headers.get("content-type") || "";
  if (!response.ok) {
    const body = type.includes("json") ? await response.json() : { error: await response.text() };
    throw new ApiError(body.error || `request failed (${response.status})`);
  }
  return response;
}

export async function get(path) {
  const response = await answer(await fetch(path, { headers: { "X-Isotween-Token": token } }));
  return response.json();
}

export async function post(path, body) {
  const init = { method: "POST", headers: { "X-Isotween-Token": token } };
  if (body instanceof FormData) init.body = body;
  else if (typeof body === "string") { init.body = body; init.headers["Content-Type"] = "application/json"; }
  else { init.body = JSON.stringify(body ?? {}); init.headers["Content-Type"] = "application/json"; }
  return answer(await fetch(path, init));
}

export async function postJson(path, body) {
  return (await post(path, body)).json();
}

// base64 little-endian bytes -> typed array (a plain loop: a callback per byte takes 0.1 s on 10k-vertex frames)
export function unpack(text, Kind = Float64Array) {
  const raw = atob(text);
  const bytes = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
  return new Kind(bytes.buffer);
}

export function download(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement("a");
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
