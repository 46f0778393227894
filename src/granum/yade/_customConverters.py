"""``yade._customConverters``: in YADE, the registration of converters between Python sequences and C++
containers. granum's classes take Python sequences directly, so the module has nothing to export; it
exists because YADE scripts and tests write ``from yade._customConverters import *``."""

__all__: list[str] = []
