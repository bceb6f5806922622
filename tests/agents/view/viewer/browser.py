"""Headless Debian Chromium driven by Selenium (python3-selenium, chromium-driver), for the
viewer's tests and benchmark. Loopback only: background networking is off."""
import os
import tempfile

from selenium import webdriver
from selenium.webdriver.chrome.service import Service


def chromium(width=1400, height=900):
    opts = webdriver.ChromeOptions()
    opts.binary_location = "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
              "--disable-background-networking", "--disable-component-update", "--disable-sync",
              "--disable-dev-shm-usage", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
              "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
              f"--window-size={width},{height}", "--user-data-dir=" + tempfile.mkdtemp(prefix="quiver-chromium-")):
        opts.add_argument(a)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)


def wait_for(driver, script, timeout_s=10.0, poll_s=0.02):
    """Polls a JS expression until it is truthy; returns its value, or raises with the last value."""
    import time
    end = time.monotonic() + timeout_s
    value = None
    while time.monotonic() < end:
        value = driver.execute_script("return " + script)
        if value:
            return value
        time.sleep(poll_s)
    raise AssertionError(f"{script!r} still {value!r} after {timeout_s} s")
