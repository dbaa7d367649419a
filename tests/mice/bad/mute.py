"""Never sends a line at all."""
import time

time.sleep(60)
