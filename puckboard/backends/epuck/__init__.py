"""The physical e-puck: EPuckReal over e-puck2 Wi-Fi (TCP) or advanced sercom (serial).

``open_wifi(scene, host=...)`` and ``open_sercom(scene, device=...)`` are the backend
factories behind ``--backend epuck2-wifi`` and ``--backend sercom``. The codecs
(:mod:`.blocks`, :mod:`.wifi_codec`, :mod:`.sercom_codec`, :mod:`.units`) are pure and
shared with the robot emulator (``puckboard emulate``). pyserial is imported only when a
serial port is opened.
"""

from .adapter import EPuckReal
from .factories import open_sercom, open_wifi

__all__ = ["EPuckReal", "open_sercom", "open_wifi"]
