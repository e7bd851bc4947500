"""The tests read EXR files with the add-on's own reader (addon/exr.py: uncompressed scanline
files, single-part as Blender 3.4/4.5 write them, multi-part as 5.0 does; channel names of any
file), loaded from the source tree so that test modules can import it before the add-on is set up."""
import importlib.util
import pathlib

_spec = importlib.util.spec_from_file_location(
    "purl_addon_exr", pathlib.Path(__file__).resolve().parents[2] / "addon" / "exr.py")
_reader = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_reader)

read_channels = _reader.read_exr
channel_names = _reader.channel_names
