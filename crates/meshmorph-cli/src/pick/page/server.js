// What both pages of `meshmorph pick` ask their server by: a GET (no body)
// or a POST of JSON, the answer as JSON, bytes or a blob; a refusal thrown
// as an Error with the server's message. Every URL is relative: the page's
// address holds the session's token.

export async function request(path, body, kind = 'json') {
  const init = body === undefined ? {} : {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  };
  const response = await fetch(path, init);
  if (!response.ok) {
    let message = response.statusText;
    try { message = (await response.json()).error ?? message; } catch { /* not JSON */ }
    throw new Error(message);
  }
  if (kind === 'blob') return response.blob();
  if (kind === 'binary') return response.arrayBuffer();
  return response.json();
}
