"""A first run says it is compiling (numba) and keeps the compiler's lines off the console
(DOLFINx forms): issue 56, "A one-line notice on a first run ... The demo's compiler chatter
is hidden (logged to a file)"."""
import io
import logging
import pytest

from dem_core import jit_cache


class _Terminal(io.StringIO):
    def isatty(self):
        return True


class _EmptyCache:
    """A dispatcher whose numba cache holds nothing (a machine's first run)."""

    class _cache:
        class _cache_file:
            @staticmethod
            def _load_index():
                return {}


@pytest.fixture
def fresh(monkeypatch):
    monkeypatch.setattr(jit_cache, "_said", [False])
    monkeypatch.delenv(jit_cache.NOTICE_ENV, raising=False)


def test_an_empty_cache_gives_one_line_on_a_terminal_once_per_process(fresh):
    out = _Terminal()
    assert jit_cache.first_run_notice(_EmptyCache, out)
    assert not jit_cache.first_run_notice(_EmptyCache, out)
    lines = out.getvalue().splitlines()
    assert lines == [jit_cache.NOTICE] and "compiling" in lines[0] and "min" in lines[0]


def test_a_log_or_a_captured_stream_gets_nothing_unless_asked(fresh, monkeypatch):
    plain = io.StringIO()
    assert not jit_cache.first_run_notice(_EmptyCache, plain) and plain.getvalue() == ""
    monkeypatch.setenv(jit_cache.NOTICE_ENV, "1")
    assert jit_cache.first_run_notice(_EmptyCache, plain) and plain.getvalue()


def test_it_can_be_silenced(fresh, monkeypatch):
    monkeypatch.setenv(jit_cache.NOTICE_ENV, "0")
    out = _Terminal()
    assert not jit_cache.first_run_notice(_EmptyCache, out) and out.getvalue() == ""


def test_a_kernel_with_a_cache_entry_gives_no_notice(fresh):
    from dem_core.step import run as stepper
    from tests.test_bad_input import two_blocks

    two_blocks().cycle(2)           # compiled or loaded: either way cached now
    assert jit_cache.has_cache(stepper.run_steps)
    out = _Terminal()
    assert not jit_cache.first_run_notice(stepper.run_steps, out) and out.getvalue() == ""


# ------------------------------------------------------------------ the continuum's compiler
def test_compiler_lines_go_to_the_log_not_the_console(tmp_path, monkeypatch):
    from continuum_ref import _dolfinx05 as dx
    from dolfinx import jit

    monkeypatch.setattr(jit, "get_parameters", lambda *a: {"cache_dir": tmp_path})
    root = logging.getLogger()
    console = io.StringIO()
    handler = logging.StreamHandler(console)        # as ffcx's basicConfig() installs
    root.addHandler(handler)
    level = root.level
    try:
        with dx.compiler_log():
            root.setLevel(logging.INFO)             # as distutils does
            logging.info("x86_64-linux-gnu-gcc -O2 -c form.c")
            logging.getLogger("mine").warning("a named logger's warning")
            logging.warning("a root warning")
        assert root.level == level and handler.filters == []
    finally:
        root.removeHandler(handler)
        root.setLevel(level)
    assert "gcc" not in console.getvalue()
    assert "a named logger's warning" in console.getvalue()
    assert "a root warning" in console.getvalue()
    assert "gcc" in (tmp_path / "compile.log").read_text()
