"""USB cameras as Linux's sysfs sees them: which are plugged in, and whether we may open them.

Both libfreenect and librealsense open cameras through libusb, which needs read-write access to
`/dev/bus/usb/BBB/DDD`. Without a udev rule only root has it, and the libraries then say little
more than "no device". This module finds the camera by its USB ids without opening it, so
`issv list` can name it and say which rule to add.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

SYSFS = Path("/sys/bus/usb/devices")
DEVFS = Path("/dev/bus/usb")


@dataclass(frozen=True)
class UsbDevice:
    vendor: str  # 4 hex digits, as udev rules write them
    product: str
    model: str
    serial: str
    firmware: str  # bcdDevice: the device's release number
    node: Path  # /dev/bus/usb/BBB/DDD

    @property
    def accessible(self) -> bool:
        return os.access(self.node, os.R_OK | os.W_OK)

    def udev_rule(self) -> str:
        return (f'SUBSYSTEM=="usb", ATTR{{idVendor}}=="{self.vendor}", ATTR{{idProduct}}=="{self.product}", '
                f'MODE="0666"')


def attribute(folder: Path, name: str) -> str:
    """A sysfs attribute's text, '' when the file is not there."""
    try:
        return (folder / name).read_text().strip()
    except OSError:
        return ""


def find(ids: dict[tuple[str, str], str]) -> list[UsbDevice]:
    """Plugged-in USB devices whose (vendor, product) is a key of `ids` (value: the model name)."""
    found, sysfs = [], SYSFS
    for folder in sorted(sysfs.glob("*")) if sysfs.is_dir() else []:
        key = (attribute(folder, "idVendor").lower(), attribute(folder, "idProduct").lower())
        if key not in ids:
            continue
        bus, dev = attribute(folder, "busnum"), attribute(folder, "devnum")
        node = DEVFS / f"{int(bus or 0):03d}" / f"{int(dev or 0):03d}"
        found.append(UsbDevice(key[0], key[1], attribute(folder, "product") or ids[key], attribute(folder, "serial"),
                               attribute(folder, "bcdDevice"), node))
    return found


def permission_problem(devices: list[UsbDevice]) -> str | None:
    """None when every device can be opened; else the udev rule that lets this user open it."""
    blocked = [d for d in devices if not d.accessible]
    if not blocked:
        return None
    rules = "; ".join(sorted({d.udev_rule() for d in blocked}))
    return (f"no permission on {', '.join(str(d.node) for d in blocked)}: add the udev rule "
            f"{rules} to /etc/udev/rules.d/51-issv-cameras.rules, then `sudo udevadm control --reload` "
            f"and replug the camera")
