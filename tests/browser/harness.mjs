// Shared by the browser tests: start a `wheelpose` server and wait for its URL; open Debian's
// chromium headless on a fresh profile.
import { chromium } from 'playwright-core';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

// Runs `binary args…` and resolves with {server, url} once it prints "listening on URL".
export async function startServer(binary, args) {
  const server = spawn(binary, args);
  const url = await new Promise((resolve, reject) => {
    let out = '';
    server.stdout.on('data', (d) => {
      out += d;
      const m = /listening on (http:\/\/\S+)/.exec(out);
      if (m) resolve(m[1]);
    });
    server.stderr.on('data', (d) => { out += d; });
    server.on('exit', (code) => reject(new Error('server exited ' + code + ': ' + out)));
    setTimeout(() => reject(new Error('server did not start: ' + out)), 15000);
  });
  return { server, url };
}

// A fresh profile every run (playwright passes it to chromium as --user-data-dir); close()
// shuts the browser and removes the profile.
export async function launchBrowser(viewport) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'wheelpose-chromium-'));
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    viewport,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = browser.pages()[0] || await browser.newPage();
  const close = async () => {
    await browser.close();
    fs.rmSync(profile, { recursive: true, force: true });
  };
  return { browser, page, close };
}
