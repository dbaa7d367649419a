"""How an `asp` built by `hako build --raspike-art` starts under qemu-user with the bench's hub as its serial
port.

`asp` opens the hub at `/dev/USB_SPIKE` whatever its device config says: RasPike-ART looks up
`VDEV_SERIAL_DEV_NAME` in a constructor (target/raspi_gcc/athrill/vdev.c 146, `constructor(101)`) that runs
before `main` loads the config (main.c 29), so the default always wins (vdev_com_usb.c 27). qemu-user looks
every absolute path the program opens up in its `-L` prefix first, so a prefix folder of the run's own, with
`lib` (Debian's aarch64 libraries) and `dev/USB_SPIKE` (a link to the hub's pty), gives `asp` the bench's hub
without root and without writing `/dev`. docs/DESIGN-NOTES.md says why aarch64 at all.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from athrill_sim.raspike_art import AspError
from athrill_sim.raspike_art.build import DEVICE_CONFIG, INSTALL_CROSS, SETJMP

QEMU = "qemu-aarch64"
SYSROOT = Path("/usr/aarch64-linux-gnu")  # Debian's aarch64 libc (libc6-arm64-cross, with the cross compiler)
SERIAL = "dev/USB_SPIKE"  # vdev_com_usb.c 27


PREFIX = "asp-root"  # qemu's prefix for asp's tests, in the run directory


def prefix_links(device: str) -> dict[str, str]:
    """qemu's prefix for a run as links (name in the prefix folder, target): the aarch64 libraries, and the
    hub's pty `device` as /dev/USB_SPIKE."""
    if not (SYSROOT / "lib").is_dir():
        raise AspError(f"no aarch64 libraries at {SYSROOT}: {INSTALL_CROSS.split(': ', 1)[1]}")
    return {"lib": str(SYSROOT / "lib"), SERIAL: device}


def prefix_folder(folder: Path, device: str) -> Path:
    """`folder` made qemu's prefix for one run (`prefix_links`)."""
    for name, target in prefix_links(device).items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).symlink_to(target)
    return folder


def asp_argv(asp: Path, prefix: Path | str, preload: tuple[Path, ...] = (),
             env: tuple[tuple[str, str], ...] = ()) -> list[str]:
    """The command that starts `asp` as RasPike-ART's `make start` does (its setjmp preloaded, its device
    config), under qemu-user with `prefix`, with `preload` preloaded after the setjmp and `env` set."""
    qemu = shutil.which(QEMU)
    if qemu is None:
        raise AspError(f"no {QEMU}: {INSTALL_CROSS.split(': ', 1)[1]}")
    libraries = ":".join(str(f) for f in (asp.parent / SETJMP.name, *preload))
    return [qemu, "-L", str(prefix), "-E", f"LD_PRELOAD={libraries}",
            *(a for name, value in env for a in ("-E", f"{name}={value}")), str(asp), "-d",
            str(asp.parent / DEVICE_CONFIG.name)]
