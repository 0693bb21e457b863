"""``symdyn cache``: where the derivation cache is, what it holds, and clearing it."""

from __future__ import annotations

from ..model.errors import SymdynError

HELP = "show the derivation cache (info) or remove its entries (clear)"


def add_parser(sub) -> None:
    p = sub.add_parser("cache", help=HELP, description=HELP + ". Derivations are cached by content hash "
                       "in $SYMDYN_CACHE_DIR (default ~/.cache/symdyn); the least recently used entries "
                       "are removed beyond $SYMDYN_CACHE_MAX_MB megabytes (default 256).")
    p.add_argument("action", choices=("info", "clear"), help="info: directory, entries, size and limit; "
                   "clear: remove every entry (the next runs derive again)")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..derive.cache import Untrusted, cache_info, clear_cache
    if args.action == "info":
        info = cache_info()
        print(f"directory: {info.directory}")
        if info.usable is not None:
            print(f"not used: {info.usable}")
            return 0
        print(f"entries:   {info.entries} ({_megabytes(info.bytes)})")
        print(f"limit:     {_megabytes(info.limit)} (least recently used entries removed beyond it; "
              "$SYMDYN_CACHE_MAX_MB)")
        return 0
    try:
        count, size = clear_cache()
    except Untrusted as exc:
        raise SymdynError(f"the cache directory is not used, nothing removed: {exc}") from None
    print(f"removed {count} entr{'y' if count == 1 else 'ies'} ({_megabytes(size)})")
    return 0


def _megabytes(size: int) -> str:
    return f"{size / 2**20:.1f} MB"
