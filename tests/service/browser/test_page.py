#!/usr/bin/env python3
"""The service's page at / in real Chromium (selenium + chromedriver, Debian's packages).

Starts `yarnfit serve` on a free loopback port over a fresh data folder with one user, opens
the page, pastes the token, uploads a zipped swatch folder through the file input, starts a
shell fit from the fabrics table, watches the fit's progress bar move on its event stream
until it is done, opens the fit's report in a new window and checks it, and keeps screenshots
of both pages in SHOTS_DIR (service_page.png, service_report.png).

usage: test_page.py YARNFIT SHOTS_DIR
Exit 77 (ctest: skipped) when Chromium, chromedriver or selenium is missing, unless CI=true.
"""
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
import zipfile

SKIP = 77


def missing(what):
    if os.environ.get("CI") == "true":
        print(f"FAIL: {what} is missing, and CI=true (scripts/install_deps.sh installs it)")
        sys.exit(1)
    print(f"SKIP: {what} is missing (apt install chromium chromium-driver python3-selenium)")
    sys.exit(SKIP)


try:
    from selenium import webdriver
    from selenium.common.exceptions import NoSuchElementException, StaleElementReferenceException
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select, WebDriverWait
except ImportError:
    missing("python3-selenium")

CHROMIUM = shutil.which("chromium")
DRIVER = shutil.which("chromedriver")
if not CHROMIUM:
    missing("chromium")
if not DRIVER:
    missing("chromium-driver")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run(*args):
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"FAIL: {' '.join(args)}\n{done.stdout}{done.stderr}")
    return done.stdout


def main():
    yarnfit, shots = sys.argv[1], sys.argv[2]
    os.makedirs(shots, exist_ok=True)
    work = tempfile.mkdtemp(prefix="yarnfit_page_")
    data = os.path.join(work, "data")
    server = None
    driver = None
    try:
        token = re.search(r"token: (\S+)", run(yarnfit, "serve", "user", "add", "tess", data)).group(1)
        # A swatch folder zipped as a lab would send it: a shell-model record of known curves.
        record = os.path.join(work, "web_swatch")
        run(yarnfit, "synth", "shell", "--out", record, "--id", "web_swatch", "--family", "demo knits",
            "--weft", "0.15", "--bias", "0", "--warp", "0", "--points", "5")
        archive = os.path.join(work, "web_swatch.zip")
        with zipfile.ZipFile(archive, "w") as z:
            for name in sorted(os.listdir(record)):
                z.write(os.path.join(record, name), "web_swatch/" + name)

        port = free_port()
        base = f"http://127.0.0.1:{port}"
        server = subprocess.Popen([yarnfit, "serve", data, "--listen", f"127.0.0.1:{port}", "--jobs", "1",
                                   "--threads-per-job", "1"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        for _ in range(200):
            try:
                if urllib.request.urlopen(base + "/healthz", timeout=1).status == 200:
                    break
            except OSError:
                time.sleep(0.05)

        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1100,900"):
            options.add_argument(arg)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})  # to see what the CSP refused
        driver = webdriver.Chrome(service=Service(DRIVER), options=options)
        wait = WebDriverWait(driver, 120)
        driver.get(base + "/")
        assert driver.title == "yarnfit service", driver.title

        driver.find_element(By.ID, "token").send_keys(token)
        driver.find_element(By.ID, "use-token").click()
        wait.until(lambda d: "fabric(s)" in d.find_element(By.ID, "who").text)
        driver.find_element(By.ID, "archive").send_keys(archive)
        driver.find_element(By.ID, "upload").click()
        wait.until(lambda d: "uploaded web_swatch" in d.find_element(By.ID, "message").text)
        wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "button[data-fabric='web_swatch']"))

        # Fit it, shell only, and watch the progress bar while it runs.
        row = driver.find_element(By.CSS_SELECTOR, "button[data-fabric='web_swatch']").find_element(By.XPATH, "./..")
        Select(row.find_elements(By.TAG_NAME, "select")[1]).select_by_value("shell")
        driver.find_element(By.CSS_SELECTOR, "button[data-fabric='web_swatch']").click()
        job = "tr[data-job='web_swatch']"
        wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, job))
        widths, states = [], []
        deadline = time.time() + 600
        while time.time() < deadline:
            # Read in one script: the page re-renders the row on every event.
            seen = driver.execute_script(
                "const tr = document.querySelector(arguments[0]); if (!tr) return null;"
                "const bar = tr.querySelector('.bar > div');"
                "return [tr.dataset.state, bar ? bar.style.width : ''];", job)
            if seen:
                state, width = seen
                if not states or states[-1] != state:
                    states.append(state)
                if not widths or widths[-1] != width:
                    widths.append(width)
                if state in ("done", "failed", "cancelled"):
                    break
            time.sleep(0.1)
        print("states seen:", states)
        print("bar widths seen:", widths)
        assert states[-1] == "done", states
        assert "running" in states, states
        assert len(widths) >= 3, widths  # the bar moved while the fit ran, not only at the end
        assert widths[-1] == "100%", widths
        driver.save_screenshot(os.path.join(shots, "service_page.png"))
        # The page ran under its Content-Security-Policy (its own script only) and nothing was refused.
        refused = [e["message"] for e in driver.get_log("browser") if "Content Security Policy" in e["message"]]
        assert not refused, refused

        # The report opens in a window of its own.
        before = set(driver.window_handles)
        def click_report(d):
            try:
                d.find_element(By.CSS_SELECTOR, job + " button.report").click()
                return True
            except (NoSuchElementException, StaleElementReferenceException):
                return False  # the row was re-rendered between finding the button and the click
        wait.until(click_report)
        wait.until(lambda d: len(d.window_handles) > len(before))
        driver.switch_to.window((set(driver.window_handles) - before).pop())
        wait.until(lambda d: "web_swatch" in d.page_source)
        assert "demo knits" in driver.page_source
        driver.save_screenshot(os.path.join(shots, "service_report.png"))
        print(f"OK: screenshots in {shots}")
    finally:
        if driver:
            driver.quit()
        if server:
            server.terminate()
            out, _ = server.communicate(timeout=60)
            print(out.decode(errors="replace")[-2000:])
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
