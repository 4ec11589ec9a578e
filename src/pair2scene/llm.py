"""A small client for OpenAI-compatible chat-completions endpoints, with JSON replies.

Any server that speaks ``POST {base}/chat/completions`` works: hosted APIs, or a
local llama.cpp (``llama-server``), vLLM or Ollama (``http://127.0.0.1:11434/v1``).
The client is optional: :meth:`LLMConfig.from_env` returns None when no endpoint
is configured, and then nothing here ever opens a socket.

Environment (read by :meth:`LLMConfig.from_env`):

``PAIR2SCENE_LLM_BASE_URL``
    The API root including its version path, e.g. ``http://127.0.0.1:8080/v1``.
    Falls back to ``OPENAI_BASE_URL``. Unset: no LLM.
``PAIR2SCENE_LLM_MODEL``
    The model name the server expects (required once a base URL is set).
``PAIR2SCENE_LLM_API_KEY``
    Sent as ``Authorization: Bearer ...``; falls back to ``OPENAI_API_KEY``;
    optional (local servers need none). ``OPENAI_API_KEY`` alone, without a base
    URL, enables nothing.
``PAIR2SCENE_LLM_TIMEOUT``
    Seconds for one request (default 60).

:meth:`LLMClient.complete_json` asks for a reply that follows a JSON schema
(``response_format`` ``json_schema``, strict), and trusts nothing it gets back:
the body is read up to a byte cap, the first JSON object of the message is
parsed (servers that ignore ``response_format`` often wrap it in prose or a
```` ```json ```` fence), and it must validate against the schema, checked here
by :func:`validate_json` for the subset of JSON Schema this package uses. A
reply that fails is rejected, counted in :attr:`LLMClient.stats` and raised as
:class:`LLMReplyError`, which callers treat as "no answer for this item".
Connection errors, 5xx and 429 are retried with exponential backoff. Validated
replies are cached on disk as JSON, keyed by a hash of model, messages and
schema, so a rerun makes no request.
"""

from __future__ import annotations

import hashlib
import http.client
import ipaddress
import json
import math
import os
import re
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from email.message import Message
from pathlib import Path
from typing import Any

from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.paths import cache_dir

ENV_BASE_URL = "PAIR2SCENE_LLM_BASE_URL"
ENV_MODEL = "PAIR2SCENE_LLM_MODEL"
ENV_API_KEY = "PAIR2SCENE_LLM_API_KEY"
ENV_TIMEOUT = "PAIR2SCENE_LLM_TIMEOUT"
FALLBACK_BASE_URL = "OPENAI_BASE_URL"
FALLBACK_API_KEY = "OPENAI_API_KEY"

CACHE_VERSION = 1
"""Bumped when the cache entry's layout or key changes; old entries are then ignored."""


class LLMReplyError(Exception):
    """A reply that was rejected (malformed, oversized or off-schema). Counted, not fatal."""

    def __init__(self, kind: str, detail: str) -> None:
        self.kind = kind
        """``malformed`` or ``schema``."""
        self.detail = detail
        super().__init__(f"rejected {kind} reply: {detail}")


class SchemaError(ValueError):
    """A value that does not follow a schema (or a schema this validator does not support)."""


@dataclass(frozen=True)
class LLMConfig:
    """Where and how to reach an OpenAI-compatible chat-completions endpoint."""

    base_url: str
    """API root with its version path, e.g. ``http://127.0.0.1:8080/v1``."""
    model: str
    """Model name sent with every request."""
    api_key: str | None = field(default=None, repr=False)
    """Bearer token; None for local servers without authentication."""
    timeout_s: float = 60.0
    """Socket timeout of one request (connect and each read)."""
    total_timeout_s: float = 300.0
    """No new attempt starts once this much time has passed since the first one."""
    max_tries: int = 3
    """Attempts per call, counting the first; only connection errors, 5xx and 429 retry."""
    backoff_s: float = 0.5
    """Wait before the second attempt; doubled before each further one."""
    max_backoff_s: float = 8.0
    """Cap on one wait, also on a server's ``Retry-After``."""
    max_reply_bytes: int = 256 * 1024
    """A reply body larger than this is rejected unread: structured answers here are small."""
    temperature: float | None = 0.0
    """0 for repeatable answers (a cache hit and a fresh call then agree); None sends
    none (models that accept only their default)."""
    max_tokens: int | None = 2048
    """Completion cap sent to the server; None sends none."""

    def __post_init__(self) -> None:
        parts = urllib.parse.urlsplit(self.base_url)
        if parts.scheme not in ("http", "https") or not parts.netloc:
            raise UserError(
                f"LLM base URL {self.base_url!r} is not an http(s) URL "
                f"(e.g. http://127.0.0.1:8080/v1)"
            )
        if not self.model:
            raise UserError(f"no LLM model: set {ENV_MODEL} (e.g. the name the server serves)")
        if self.max_tries < 1 or self.timeout_s <= 0 or self.max_reply_bytes < 1:
            raise ValueError("max_tries, timeout_s and max_reply_bytes must be positive")

    @property
    def endpoint(self) -> str:
        return self.base_url.rstrip("/") + "/chat/completions"

    @classmethod
    def from_env(cls, environ: dict[str, str] | None = None) -> LLMConfig | None:
        """The configuration from the environment, or None when no base URL is set."""
        env = os.environ if environ is None else environ
        base = (env.get(ENV_BASE_URL) or env.get(FALLBACK_BASE_URL) or "").strip()
        if not base:
            return None
        key = (env.get(ENV_API_KEY) or env.get(FALLBACK_API_KEY) or "").strip() or None
        timeout = 60.0
        if raw := env.get(ENV_TIMEOUT, "").strip():
            try:
                timeout = float(raw)
            except ValueError:
                raise UserError(f"{ENV_TIMEOUT}={raw!r} is not a number of seconds") from None
            if not (math.isfinite(timeout) and timeout > 0):
                raise UserError(f"{ENV_TIMEOUT}={raw!r} must be a positive number of seconds")
        return cls(base, env.get(ENV_MODEL, "").strip(), key, timeout_s=timeout)


@dataclass
class LLMStats:
    """What a client did; every rejected reply is counted once."""

    requests: int = 0
    """HTTP requests sent (retries included)."""
    cache_hits: int = 0
    retries: int = 0
    rejected_malformed: int = 0
    """Replies that were not a chat completion with one JSON object in it, or too large."""
    rejected_schema: int = 0
    """Replies whose JSON did not follow the schema."""

    def to_dict(self) -> dict[str, int]:
        return asdict(self)


# -- JSON Schema subset ----------------------------------------------------------

_TYPES: dict[str, Callable[[Any], bool]] = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "boolean": lambda v: isinstance(v, bool),
    "null": lambda v: v is None,
}
_KEYWORDS = frozenset(
    {
        "type", "properties", "required", "additionalProperties", "items", "enum",
        "minimum", "maximum", "minItems", "maxItems", "maxLength", "description", "title",
    }
)  # fmt: skip


def validate_json(value: Any, schema: dict, path: str = "$") -> None:
    """Raise :class:`SchemaError` unless ``value`` follows ``schema``.

    Supports ``type`` (one name or a list), ``properties``, ``required``,
    ``additionalProperties`` (``false`` only), ``items``, ``enum``, ``minimum``,
    ``maximum``, ``minItems``, ``maxItems``, ``maxLength`` and the annotations
    ``description`` and ``title``. Any other keyword is an error, so a schema
    never silently promises a check that is not made.
    """
    if not isinstance(schema, dict):
        raise SchemaError(f"schema at {path} is not an object")
    unknown = set(schema) - _KEYWORDS
    if unknown:
        raise SchemaError(f"schema at {path} uses unsupported keywords {sorted(unknown)}")
    if "type" in schema:
        names = schema["type"] if isinstance(schema["type"], list) else [schema["type"]]
        for name in names:
            if name not in _TYPES:
                raise SchemaError(f"schema at {path}: unknown type {name!r}")
        if not any(_TYPES[n](value) for n in names):
            raise SchemaError(f"{path}: expected {'/'.join(names)}, got {type(value).__name__}")
    if isinstance(value, float) and not math.isfinite(value):
        raise SchemaError(f"{path}: not a finite number")
    if "enum" in schema and not any(value == e and type(value) is type(e) for e in schema["enum"]):
        raise SchemaError(f"{path}: {_short(value)} is not one of the allowed values")
    if _TYPES["number"](value):
        if "minimum" in schema and value < schema["minimum"]:
            raise SchemaError(f"{path}: {value} < minimum {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            raise SchemaError(f"{path}: {value} > maximum {schema['maximum']}")
    if isinstance(value, str) and "maxLength" in schema and len(value) > schema["maxLength"]:
        raise SchemaError(f"{path}: string longer than {schema['maxLength']}")
    if isinstance(value, list):
        if "maxItems" in schema and len(value) > schema["maxItems"]:
            raise SchemaError(f"{path}: more than {schema['maxItems']} items")
        if "minItems" in schema and len(value) < schema["minItems"]:
            raise SchemaError(f"{path}: fewer than {schema['minItems']} items")
        if "items" in schema:
            for i, item in enumerate(value):
                validate_json(item, schema["items"], f"{path}[{i}]")
    if isinstance(value, dict):
        props = schema.get("properties", {})
        for key in schema.get("required", ()):
            if key not in value:
                raise SchemaError(f"{path}: missing {key!r}")
        extra = schema.get("additionalProperties", True)
        if extra not in (True, False):
            raise SchemaError(f"schema at {path}: additionalProperties must be true or false")
        if extra is False and (unexpected := set(value) - set(props)):
            raise SchemaError(f"{path}: unexpected keys {_short(sorted(unexpected))}")
        for key, sub in props.items():
            if key in value:
                validate_json(value[key], sub, f"{path}.{key}")


def _short(value: Any, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


# -- parsing replies ---------------------------------------------------------------

_FENCE = re.compile(r"```(?:json|JSON)?[ \t]*\r?\n(.*?)```", re.DOTALL)
_MAX_OBJECT_STARTS = 64
"""Positions of ``{`` tried when hunting for an object in prose: bounds the work on junk."""


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def _loads(text: str) -> Any:
    # NaN/Infinity are not JSON; Python accepts them unless told otherwise.
    return json.loads(text, parse_constant=_reject_constant)


def extract_json_object(content: str) -> dict:
    """The first JSON object in a message: the whole text, a ```json fence, or prose around it.

    Raises ValueError when there is none.
    """
    candidates = [content.strip()]
    candidates += [m.group(1).strip() for m in _FENCE.finditer(content)]
    for text in candidates:
        try:
            value = _loads(text)
        except (ValueError, RecursionError):
            continue
        if isinstance(value, dict):
            return value
    decoder = json.JSONDecoder(parse_constant=_reject_constant)
    start = content.find("{")
    for _ in range(_MAX_OBJECT_STARTS):
        if start < 0:
            break
        try:
            value, _end = decoder.raw_decode(content, start)
        except (ValueError, RecursionError):
            value = None
        if isinstance(value, dict):
            return value
        start = content.find("{", start + 1)
    raise ValueError("no JSON object in the reply")


# -- HTTP ---------------------------------------------------------------------------


class _NoRedirect(urllib.request.HTTPRedirectHandler):
    """Redirects are refused: following one would resend the API key to another URL."""

    def redirect_request(self, req, fp, code, msg, headers, newurl):  # noqa: D102
        raise urllib.error.HTTPError(req.full_url, code, f"redirect to {newurl}", headers, fp)


def _is_loopback(host: str | None) -> bool:
    if not host:
        return False
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _opener(url: str) -> urllib.request.OpenerDirector:
    handlers: list[urllib.request.BaseHandler] = [_NoRedirect()]
    if _is_loopback(urllib.parse.urlsplit(url).hostname):
        handlers.append(urllib.request.ProxyHandler({}))  # a local server is never proxied
    return urllib.request.build_opener(*handlers)


class _Retryable(Exception):
    def __init__(self, reason: str, retry_after: float | None = None) -> None:
        self.reason, self.retry_after = reason, retry_after
        super().__init__(reason)


class _FormatRefused(Exception):
    """HTTP 400 naming ``response_format``: the server does not take structured output."""


def _mentions_format(detail: str) -> bool:
    low = detail.lower()
    return any(w in low for w in ("response_format", "json_schema", "response format"))


def _retry_after(headers: Message | None) -> float | None:
    raw = headers.get("Retry-After") if headers is not None else None
    try:
        value = float(raw) if raw is not None else None
    except ValueError:
        return None
    return value if value is not None and math.isfinite(value) and value >= 0 else None


class LLMClient:
    """Structured (JSON) completions from an OpenAI-compatible endpoint, cached on disk.

    ``cache_dir`` None disables the cache. ``sleep`` is the wait used between
    retries (tests pass a recorder).
    """

    def __init__(
        self,
        config: LLMConfig,
        cache_dir: str | os.PathLike | None = None,
        *,
        use_cache: bool = True,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        if not isinstance(config, LLMConfig):
            raise TypeError("LLMClient needs an LLMConfig (LLMConfig.from_env() may be None)")
        self.config = config
        self.cache_dir = None if not use_cache else Path(cache_dir or default_cache_dir())
        self.stats = LLMStats()
        self._sleep = sleep
        self._opener = _opener(config.endpoint)

    # -- public ------------------------------------------------------------------
    def complete_json(self, messages: Sequence[dict], schema: dict, name: str) -> dict:
        """Send ``messages`` and return the reply's JSON object, validated against ``schema``.

        messages : chat messages ``{"role": "system"|"user"|"assistant", "content": str}``.
        schema   : a JSON schema of the subset :func:`validate_json` supports; its
                   top level must be an object.
        name     : the schema's name (``[A-Za-z0-9_-]``, at most 64 characters).
        Raises :class:`LLMReplyError` for a rejected reply and :class:`UserError`
        when the endpoint cannot be used at all (unreachable, refused the key...).
        """
        if not re.fullmatch(r"[A-Za-z0-9_-]{1,64}", name):
            raise ValueError(f"schema name {name!r} must match [A-Za-z0-9_-]{{1,64}}")
        if schema.get("type") != "object":
            raise ValueError("the top level of a reply schema must be an object")
        _check_schema(schema)
        messages = [{"role": m["role"], "content": m["content"]} for m in messages]
        key = self.cache_key(messages, schema, name)
        cached = self._read_cache(key, schema)
        if cached is not None:
            self.stats.cache_hits += 1
            return cached
        body = {
            "model": self.config.model,
            "messages": messages,
            "response_format": {
                "type": "json_schema",
                "json_schema": {"name": name, "schema": schema, "strict": True},
            },
        }
        if self.config.temperature is not None:
            body["temperature"] = self.config.temperature
        if self.config.max_tokens is not None:
            body["max_tokens"] = self.config.max_tokens
        raw = self._post(body)
        reply = self._parse(raw, schema)
        self._write_cache(key, name, reply)
        return reply

    def cache_key(self, messages: Sequence[dict], schema: dict, name: str) -> str:
        """sha256 over (cache version, model, messages, schema name, schema)."""
        blob = json.dumps(
            [CACHE_VERSION, self.config.model, list(messages), name, schema],
            sort_keys=True,
            ensure_ascii=True,
            separators=(",", ":"),
        )
        return hashlib.sha256(blob.encode()).hexdigest()

    # -- transport ---------------------------------------------------------------
    def _post(self, body: dict) -> bytes:
        """POST ``body``; retry connection errors, 5xx and 429; return the raw reply body.

        A server that answers 400 to ``response_format`` (some local servers know
        no ``json_schema``) is asked once more without it: the reply is validated
        here either way.
        """
        cfg = self.config
        headers = {"Content-Type": "application/json", "Accept": "application/json"}
        if cfg.api_key:
            headers["Authorization"] = f"Bearer {cfg.api_key}"
        start = time.monotonic()
        last, retry_after, attempt, tries = "", None, 0, 0
        while tries < cfg.max_tries:
            if attempt:
                wait = min(cfg.backoff_s * 2 ** (attempt - 1), cfg.max_backoff_s)
                if retry_after is not None:
                    wait = min(max(wait, retry_after), cfg.max_backoff_s)
                if time.monotonic() - start + wait > cfg.total_timeout_s:
                    last += f" (gave up: {cfg.total_timeout_s:g} s total)"
                    break
                self.stats.retries += 1
                self._sleep(wait)
            self.stats.requests += 1
            tries += 1
            data = json.dumps(body).encode()
            request = urllib.request.Request(cfg.endpoint, data=data, headers=headers)
            try:
                return self._send(request)
            except _Retryable as exc:
                last, retry_after, attempt = exc.reason, exc.retry_after, attempt + 1
            except _FormatRefused:
                body = {k: v for k, v in body.items() if k != "response_format"}
                tries -= 1  # not the server's failure: this attempt does not count
        raise UserError(f"LLM endpoint {cfg.endpoint} failed after {tries} tries: {last}")

    def _send(self, request: urllib.request.Request) -> bytes:
        cfg = self.config
        try:
            with self._opener.open(request, timeout=cfg.timeout_s) as response:
                length = response.headers.get("Content-Length")
                if length is not None and length.isdigit() and int(length) > cfg.max_reply_bytes:
                    self._reject("malformed", f"reply of {length} bytes is over the cap")
                raw = self._read_body(response)
        except urllib.error.HTTPError as exc:
            status = exc.code
            detail = _error_detail(exc)
            if status == 429 or status >= 500:
                raise _Retryable(f"HTTP {status} {detail}", _retry_after(exc.headers)) from None
            if status in (401, 403):
                raise UserError(
                    f"LLM endpoint {cfg.endpoint} refused the request (HTTP {status}): "
                    f"check {ENV_API_KEY}"
                ) from None
            if status == 404:
                raise UserError(
                    f"LLM endpoint {cfg.endpoint} or model {cfg.model!r} not found (HTTP 404: "
                    f"{detail}); {ENV_BASE_URL} should be the API root, e.g. "
                    f"http://127.0.0.1:8080/v1"
                ) from None
            if (
                status == 400
                and _mentions_format(detail)
                and b"response_format" in (request.data or b"")
            ):
                raise _FormatRefused(detail) from None
            if 300 <= status < 400:
                raise UserError(
                    f"LLM endpoint {cfg.endpoint} redirects ({detail}): set {ENV_BASE_URL} "
                    f"to the final URL"
                ) from None
            raise UserError(
                f"LLM endpoint {cfg.endpoint} answered HTTP {status}: {detail}"
            ) from None
        except (urllib.error.URLError, OSError, http.client.HTTPException) as exc:
            reason = getattr(exc, "reason", exc)
            raise _Retryable(f"{type(exc).__name__}: {reason}") from None
        if len(raw) > cfg.max_reply_bytes:
            self._reject("malformed", f"reply over {cfg.max_reply_bytes} bytes")
        return raw

    def _read_body(self, response) -> bytes:
        """At most ``max_reply_bytes + 1`` bytes, within ``timeout_s`` of the headers: a
        server that drips its reply cannot hold a run for longer."""
        cfg = self.config
        deadline = time.monotonic() + cfg.timeout_s
        chunks: list[bytes] = []
        size = 0
        read = getattr(response, "read1", response.read)  # read1: what has arrived, no waiting
        while size <= cfg.max_reply_bytes:
            chunk = read(min(65536, cfg.max_reply_bytes + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
            if time.monotonic() > deadline:
                raise _Retryable(f"reply body not complete after {cfg.timeout_s:g} s")
        return b"".join(chunks)

    # -- reply -------------------------------------------------------------------
    def _parse(self, raw: bytes, schema: dict) -> dict:
        try:
            envelope = _loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):
            self._reject("malformed", "body is not JSON")
        content = _message_content(envelope)
        if content is None:
            self._reject("malformed", "no choices[0].message.content string")
        try:
            value = extract_json_object(content)
        except ValueError as exc:
            self._reject("malformed", str(exc))
        try:
            validate_json(value, schema)
        except SchemaError as exc:
            self._reject("schema", str(exc))
        return value

    def _reject(self, kind: str, detail: str):
        if kind == "schema":
            self.stats.rejected_schema += 1
        else:
            self.stats.rejected_malformed += 1
        raise LLMReplyError(kind, detail)

    # -- cache -------------------------------------------------------------------
    def _cache_path(self, key: str) -> Path | None:
        return None if self.cache_dir is None else self.cache_dir / key[:2] / f"{key}.json"

    def _read_cache(self, key: str, schema: dict) -> dict | None:
        path = self._cache_path(key)
        if path is None or not path.is_file():
            return None
        try:
            entry = _loads(path.read_text(encoding="utf-8"))
            reply = entry["reply"]
            validate_json(reply, schema)
        except (OSError, ValueError, KeyError, TypeError, RecursionError, SchemaError):
            return None  # a damaged or stale entry is refetched and overwritten
        return reply

    def _write_cache(self, key: str, name: str, reply: dict) -> None:
        path = self._cache_path(key)
        if path is None:
            return
        entry = {"version": CACHE_VERSION, "model": self.config.model, "name": name, "reply": reply}
        try:
            atomic_write_text(path, json.dumps(entry, indent=1, sort_keys=True) + "\n")
        except OSError:
            pass  # a cache that cannot be written (read-only, full) only costs a rerun


def default_cache_dir() -> Path:
    """``cache_dir()/llm``: where replies are kept between runs."""
    return cache_dir() / "llm"


def _error_detail(exc: urllib.error.HTTPError, limit: int = 200) -> str:
    try:
        text = exc.read(4096).decode("utf-8", "replace")
    except Exception:  # the error body is only for the message
        text = ""
    text = " ".join(text.split()) or str(exc.reason)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _message_content(envelope: Any) -> str | None:
    if not isinstance(envelope, dict):
        return None
    choices = envelope.get("choices")
    if not isinstance(choices, list) or not choices or not isinstance(choices[0], dict):
        return None
    message = choices[0].get("message")
    if not isinstance(message, dict):
        return None
    content = message.get("content")
    return content if isinstance(content, str) else None


def _check_schema(schema: dict) -> None:
    """Fail early on a schema the validator cannot enforce (walks every sub-schema)."""
    stack = [schema]
    while stack:
        sub = stack.pop()
        if not isinstance(sub, dict) or set(sub) - _KEYWORDS:
            raise ValueError(f"unsupported schema: {_short(sub)}")
        stack.extend(sub.get("properties", {}).values())
        if "items" in sub:
            stack.append(sub["items"])
