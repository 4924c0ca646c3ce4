"""Control token policy: bound to loopback no token is needed (only local users can reach the
port); bound to any other address a token is required to drive, set by the user or generated."""
import hmac
import ipaddress
import secrets

MIN_TOKEN_CHARS = 8


class ConfigError(ValueError):
    """A bad parameter; str() names it."""


def is_loopback(host):
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        # A hostname other than localhost may resolve to anything: treat it as public.
        return False


def resolve_token(host, token):
    """Returns (token or None when not required, generated?). Raises ConfigError on a bad ~token."""
    if not isinstance(token, str):
        raise ConfigError("~token must be a string, got %r" % (token,))
    if token:
        if len(token) < MIN_TOKEN_CHARS or not token.isprintable() or token.strip() != token:
            raise ConfigError("~token must be at least %d printable characters without surrounding "
                              "spaces" % MIN_TOKEN_CHARS)
        return token, False
    if is_loopback(host):
        return None, False
    return secrets.token_urlsafe(18), True


def token_matches(expected, given):
    """Constant-time comparison, so response timing does not leak the token. Total over str:
    a lone surrogate (from a JSON \\uXXXX escape) encodes to bytes no real token has."""
    return hmac.compare_digest(expected.encode("utf-8", "surrogatepass"),
                               given.encode("utf-8", "surrogatepass"))
