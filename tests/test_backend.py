"""Dr.Jit back-end selection: libLLVM discovery and the error that says how to fix it."""

import os

import pytest

from csuas.render import backend


def _touch(folder, name):
    path = folder / name
    path.write_bytes(b"")
    return path


def test_newest_usable_libllvm_is_chosen(tmp_path):
    for name in ("libLLVM-14.so", "libLLVM-15.so.1", "libLLVM-17.so", "libLLVM-19.so", "libLLVM.so.18"):
        _touch(tmp_path, name)
    assert backend.find_libllvm((str(tmp_path),)) == str(tmp_path / "libLLVM-19.so")


def test_only_broken_versions_means_none(tmp_path):
    _touch(tmp_path, "libLLVM-14.so")
    _touch(tmp_path, "libLLVM-15.so")
    assert backend.find_libllvm((str(tmp_path),)) is None


def test_missing_libllvm_error_says_how_to_fix(monkeypatch):
    monkeypatch.setenv("DRJIT_LIBLLVM_PATH", "")  # empty counts as unset; setenv restores it afterwards
    monkeypatch.setattr(backend, "find_libllvm", lambda *a: None)
    with pytest.raises(backend.BackendError, match="apt-get install -y libllvm19"):
        backend.ensure_libllvm()


def test_wrong_environment_variable_is_reported(monkeypatch, tmp_path):
    monkeypatch.setenv("DRJIT_LIBLLVM_PATH", str(tmp_path / "nope.so"))
    with pytest.raises(backend.BackendError, match="DRJIT_LIBLLVM_PATH"):
        backend.ensure_libllvm()


def test_unset_variable_is_filled_in(monkeypatch, tmp_path):
    lib = _touch(tmp_path, "libLLVM-19.so")
    monkeypatch.setenv("DRJIT_LIBLLVM_PATH", "")  # empty counts as unset; setenv restores it afterwards
    monkeypatch.setattr(backend, "find_libllvm", lambda *a: str(lib))
    assert backend.ensure_libllvm() == str(lib)
    assert os.environ["DRJIT_LIBLLVM_PATH"] == str(lib)


def test_unknown_variant_is_an_error():
    with pytest.raises(backend.BackendError, match="variant='cuda_ad_banana'"):
        backend.use_variant(variant="cuda_ad_banana")


@pytest.mark.gpu
def test_cuda_variant_when_a_gpu_is_present():
    if not backend.cuda_available():
        pytest.skip("no CUDA device")
    assert backend.use_variant("ad_rgb").startswith("cuda_")
