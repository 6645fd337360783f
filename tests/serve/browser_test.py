"""serve in a real browser (headless Chromium via selenium and chromium-driver; ctest serve_browser).

Loads the page, changes keys by typing, reads the shown c1..c4 and compares them with error_spectrum's for
the same keys (the spectra table's 10 significant digits: relative 1e-9); a bad value shows the one-line
message and the page recovers; "copy as TOML" and "copy as command line" give runs of error_spectrum with
the same c1. Optionally saves a screenshot.
Usage: browser_test.py BIN_DIR [SCREENSHOT.png]
"""
import csv
import io
import pathlib
import shlex
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select, WebDriverWait

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from serve_process import running_serve  # noqa: E402

BIN = pathlib.Path(sys.argv[1])
SHOT = sys.argv[2] if len(sys.argv) > 2 else None
REL = 1e-9


def error_spectrum(*args):
    r = subprocess.run([str(BIN / "error_spectrum"), *args], capture_output=True, text=True, check=True)
    row = list(csv.DictReader(io.StringIO(r.stdout)))[0]
    return [float(row[f"c{n}_deg"]) for n in range(1, 5)]


def settle(driver):
    """Waits until a what-if answered after the last keystroke (the shown count stops for 0.8 s)."""
    last, since = None, time.time()
    while time.time() - since < 0.8:
        now = driver.execute_script("return document.body.dataset.shown || '0'")
        if now != last:
            last, since = now, time.time()
        time.sleep(0.05)


def type_into(driver, key, text):
    e = driver.find_element(By.CSS_SELECTOR, f'[data-key="{key}"]')
    e.clear()
    e.send_keys(text)


def shown_c(driver):
    return [float(driver.find_element(By.ID, f"c{n}").get_attribute("data-value")) for n in range(1, 5)]


def same(what, got, want):
    for n, (g, w) in enumerate(zip(got, want), 1):
        assert abs(g - w) <= REL * max(abs(w), 1e-12), f"{what}: c{n} shown {g!r}, error_spectrum {w!r}"


opts = webdriver.ChromeOptions()
opts.binary_location = "/usr/bin/chromium"
for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000"):
    opts.add_argument(a)
with running_serve(BIN / "serve") as url, tempfile.TemporaryDirectory() as tmp:
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
    try:
        driver.get(url)
        WebDriverWait(driver, 30).until(lambda d: d.execute_script("return document.body.dataset.shown") == "1")
        same("defaults", shown_c(driver), error_spectrum())
        # a what-if: dynamic eccentricity 0.1 mm, probes at 2.0 mm, a diff4 array
        type_into(driver, "mount.dx_mm", "0.1")
        type_into(driver, "sensor.r0_mm", "2.0")
        type_into(driver, "mount.sx_mm", "0.05")
        type_into(driver, "mount.tilt_x_deg", "0.5")
        settle(driver)
        want = error_spectrum("--dx", "0.1", "--r0", "2.0", "--sx", "0.05", "--set", "mount.tilt_x_deg=0.5")
        same("dx 0.1, r0 2.0, sx 0.05, tilt_x 0.5", shown_c(driver), want)
        print("shown c1..c4 equal error_spectrum's:", want)
        # copy as TOML / as command line: both are runs with the same numbers
        driver.find_element(By.ID, "copy-toml").click()
        toml = driver.find_element(By.ID, "copied").get_attribute("value")
        (pathlib.Path(tmp) / "w.toml").write_text(toml)
        same("copy as TOML", error_spectrum("--config", str(pathlib.Path(tmp) / "w.toml")), want)
        driver.find_element(By.ID, "copy-cli").click()
        cli = shlex.split(driver.find_element(By.ID, "copied").get_attribute("value"))
        assert cli[0] == "error_spectrum", cli
        same("copy as command line", error_spectrum(*cli[1:]), want)
        # a bad value: the one-line message in the page, the last good numbers stay; then it recovers
        type_into(driver, "mount.dx_mm", "abc")
        settle(driver)
        msg = driver.find_element(By.ID, "error").text
        assert "mount.dx_mm" in msg and "allowed" in msg and "\n" not in msg, msg
        print("bad value shown as:", msg)
        type_into(driver, "mount.dx_mm", "0.1")
        Select(driver.find_element(By.CSS_SELECTOR, '[data-key="sensor.principle"]'))  # present
        settle(driver)
        assert driver.find_element(By.ID, "error").text == ""
        same("after the bad value", shown_c(driver), want)
        if SHOT:
            driver.save_screenshot(SHOT)
    finally:
        driver.quit()
print("serve in Chromium: c1..c4 equal error_spectrum's; bad input shown; the copies run")
