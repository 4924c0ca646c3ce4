"""Debian's headless chromium under Selenium (chromedriver), isolated and quiet, for the tests."""
import shutil
import tempfile

from selenium import webdriver
from selenium.webdriver.chrome.service import Service


class Chromium:
    """A browser with a fresh profile that is removed on quit()."""

    def __init__(self, size="1280,800"):
        self.profile = tempfile.mkdtemp(prefix="mybot-web-chromium-")
        opts = webdriver.ChromeOptions()
        opts.binary_location = shutil.which("chromium") or "/usr/bin/chromium"
        # Nothing reaches the network: no sync, updates, field trials or QUIC probing.
        for a in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--user-data-dir=" + self.profile, "--window-size=" + size):
            opts.add_argument(a)
        service = Service(shutil.which("chromedriver") or "/usr/bin/chromedriver")
        try:
            self.driver = webdriver.Chrome(service=service, options=opts)
        except Exception:
            shutil.rmtree(self.profile, ignore_errors=True)
            raise

    def quit(self):
        try:
            self.driver.quit()
        finally:
            shutil.rmtree(self.profile, ignore_errors=True)
