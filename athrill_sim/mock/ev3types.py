"""EV3RT's types and constants (ev3api_*.h, TOPPERS' t_stddef.h), for the Python mock's programs: the values are
EV3RT's, so a program reads as its C original."""

from __future__ import annotations

from dataclasses import dataclass

# TOPPERS error codes.
E_NOMEM = -33
E_NOID = -34
E_OK = 0
E_TMOUT = -50
TMO_FEVR = -1
E_PAR = -17
E_ID = -18
E_OBJ = -41

EV3_PORT_A, EV3_PORT_B, EV3_PORT_C, EV3_PORT_D = range(4)
EV3_PORT_1, EV3_PORT_2, EV3_PORT_3, EV3_PORT_4 = range(4)
SENSOR_PORTS = 4

# sensor_type_t and motor_type_t
NONE_SENSOR, ULTRASONIC_SENSOR, GYRO_SENSOR, TOUCH_SENSOR, COLOR_SENSOR = range(5)
NONE_MOTOR, MEDIUM_MOTOR, LARGE_MOTOR, UNREGULATED_MOTOR = range(4)

# ledcolor_t: bits of the TX LED word
LED_OFF, LED_RED, LED_GREEN, LED_ORANGE = 0, 1, 2, 3

# button_t: bits of the RX buttons word
LEFT_BUTTON, RIGHT_BUTTON, UP_BUTTON, DOWN_BUTTON, ENTER_BUTTON, BACK_BUTTON = range(6)

TOUCH_THRESHOLD = 2048  # ADC_RES / 2



EV3_SERIAL_DEFAULT, EV3_SERIAL_UART, EV3_SERIAL_BT = range(3)  # serial_port_t
EV3_FONT_SMALL, EV3_FONT_MEDIUM = range(2)  # lcdfont_t
EV3_LCD_WHITE, EV3_LCD_BLACK = range(2)  # lcdcolor_t
EV3_LCD_WIDTH, EV3_LCD_HEIGHT = 178, 128
TNUM_BUTTON = 6


@dataclass
class RgbRaw:
    """rgb_raw_t: what ev3_color_sensor_get_rgb_raw fills (and leaves alone on an error)."""

    r: int = 0
    g: int = 0
    b: int = 0


@dataclass
class MemFile:
    """memfile_t: a whole file in memory (ev3_memfile_load); `buffer` None once freed or when not loaded."""

    buffer: bytes | None = None
    filesz: int = 0
    buffersz: int = 0


@dataclass
class FileInfo:
    """fileinfo_t, of one entry of an SD card folder (ev3_sdcard_readdir)."""

    name: str = ""
    size: int = 0
    date: int = 0
    time: int = 0
    is_dir: bool = False
    is_readonly: bool = False
    is_hidden: bool = False
