// The viewer page in headless Chromium (Playwright). troupe-sim serves
// swarm100.world with its viewer; the test checks that the page shows every
// robot, that pause stops simulated time and resume restarts it, that
// dragging a robot teleports it (its ground truth asked with `troupe req`),
// that a WebSocket sending garbage is closed while the page goes on, and
// that troupe-view shows a live troupe-node's devices (a kinematic base
// driven with `troupe cmd`; with the shared data, a CARMEN log's laser and
// odometry). In blobs.world it checks that a blobfinder's blobs are drawn
// in the world view where the boxes it sees are (their positions and the
// canvas pixels there), and that the page reconnects by itself when the
// simulator (or, under troupe-view, the node) is killed and restarted
// behind it. In camera.world it checks that the selected robot's camera
// image in the panel (PNG, decoded by the browser) has the pixels a wire
// client reads raw. Under mpirun (when troupe-sim was built with MPI) it
// checks that the page draws every robot of a world divided between two
// processes, where the world has them. Screenshots are kept in the build tree.
//
// usage: node viewer_browser_test.mjs --bin DIR --node PATH --modules DIR --source DIR --out DIR [--shared DIR]
//        [--mpirun PATH]
// Exit 0: passed, 1: failed, 77: skipped (no Chromium).
import { spawn, execFile } from 'node:child_process';
import { existsSync, mkdtempSync, writeFileSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const args = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const kChromium = '/usr/bin/chromium';
// Every wait is for a condition; this only bounds a broken run.
const kDeadlineMs = 60000;

if (!existsSync(kChromium)) {
  console.log(`SKIP: ${kChromium} is missing (Debian: apt-get install chromium)`);
  process.exit(77);
}
const require = createRequire(join(args.modules, 'noop.js'));
const { chromium } = require('playwright-core');

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ': ' + detail : ''}`);
  if (!ok) failures++;
  return ok;
}

const children = [];
/// Starts a program and resolves with it once `pattern` matched a line of
/// its output (stdout or stderr); the match is returned too.
function start(program, argv, patterns) {
  return new Promise((resolve, reject) => {
    const child = spawn(program, argv, { stdio: ['ignore', 'pipe', 'pipe'] });
    children.push(child);
    let out = '';
    const found = {};
    const timer = setTimeout(() => reject(new Error(`${program}: no ${Object.keys(patterns)} in:\n${out}`)),
                             kDeadlineMs);
    const onData = (d) => {
      out += d.toString();
      for (const [k, re] of Object.entries(patterns)) {
        const m = out.match(re);
        if (m) found[k] = m[1];
      }
      if (Object.keys(found).length === Object.keys(patterns).length) {
        clearTimeout(timer);
        resolve({ child, ...found });
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('exit', (code) => reject(new Error(`${program} exited (${code}):\n${out}`)));
  });
}

function run(program, argv) {
  return new Promise((resolve, reject) => {
    execFile(program, argv, { timeout: kDeadlineMs }, (err, stdout, stderr) => {
      if (err) reject(new Error(`${program} ${argv.join(' ')}: ${err.message}\n${stderr}`));
      else resolve(stdout);
    });
  });
}

async function waitFor(page, fn, arg) {
  try {
    await page.waitForFunction(fn, arg, { timeout: kDeadlineMs, polling: 50 });
  } catch (e) {
    const now = await page.evaluate(() => JSON.stringify({ steps: troupeViewer.steps, t: troupeViewer.simTime,
                                                           paused: troupeViewer.paused, pending: troupeViewer.pendingRequests,
                                                           status: document.getElementById('status').textContent }))
                      .catch(() => '?');
    await page.screenshot({ path: join(args.out, 'viewer-failed.png') }).catch(() => {});
    throw new Error(`waiting for ${fn} (${JSON.stringify(arg)}; now ${now}): ${e.message}`);
  }
}

async function simulatorPage(browser) {
  const troupe = join(args.bin, 'troupe');
  const sim = await start(join(args.bin, 'troupe-sim'),
                          [join(args.source, 'examples/worlds/swarm100.world'), '--no-ctrl', '--port', '0',
                           '--view', '0'],
                          { port: /listening on [^\n]*:(\d+)\n/, url: /viewer at (\S+)\n/ });
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  page.on('pageerror', (e) => check(false, 'no error on the page', e.message));
  page.on('console', (m) => console.log(`page console: ${m.text()}`));
  await page.goto(sim.url);
  await waitFor(page, () => window.troupeViewer?.ready);

  const names = await page.evaluate(() => troupeViewer.robots());
  check(names.length === 100, 'the page lists 100 robots', `${names.length}`);
  check(names[0] === 'b0' && names[99] === 'b99', 'robots by their world-file names', `${names[0]}..${names[99]}`);
  const items = await page.locator('#robots li[data-robot]').count();
  check(items === 100, 'one list entry per robot', `${items}`);
  const pose = await page.evaluate(() => troupeViewer.pose('b44'));
  const truth = JSON.parse((await run(troupe, ['req', `127.0.0.1:${sim.port}`, 'simulation:0', 'getpose', 'b44']))
                             .replace(/^[^{]*/, ''));
  check(Math.hypot(pose.x - truth.pose.x, pose.y - truth.pose.y) < 1e-3, 'b44 is drawn at its ground truth',
        `${JSON.stringify(pose)} vs ${JSON.stringify(truth.pose)}`);

  // Running: simulated time advances; paused, it stops; resumed, it goes on.
  const t0 = await page.evaluate(() => troupeViewer.simTime);
  await waitFor(page, (t) => troupeViewer.simTime > t + 0.3, t0);
  check(true, 'simulated time advances while running');
  await page.click('#pause');
  await waitFor(page, () => troupeViewer.paused === true);
  const paused = await page.evaluate(() => ({ t: troupeViewer.simTime, steps: troupeViewer.steps }));
  // The clock itself, asked over the wire (at speed 1 a step is due every 0.1 s).
  const clock1 = await run(troupe, ['req', `127.0.0.1:${sim.port}`, 'simulation:0', 'clock']);
  await page.waitForTimeout(1000);
  const clock2 = await run(troupe, ['req', `127.0.0.1:${sim.port}`, 'simulation:0', 'clock']);
  const steps = (s) => s.match(/steps=(\d+)/)?.[1];
  check(steps(clock1) === steps(clock2) && steps(clock1) !== undefined, 'paused: the simulation takes no steps',
        `${steps(clock1)} then ${steps(clock2)}`);
  const later = await page.evaluate(() => ({ t: troupeViewer.simTime, steps: troupeViewer.steps }));
  check(later.t === paused.t && later.steps === paused.steps, 'paused: the page\'s clock stands still',
        `${paused.t} s then ${later.t} s`);
  await page.click('#pause');
  await waitFor(page, (t) => !troupeViewer.paused && troupeViewer.simTime > t, paused.t);
  check(true, 'resumed: simulated time advances again');
  await page.click('#pause');
  await waitFor(page, () => troupeViewer.paused === true);
  const stepsBefore = await page.evaluate(() => troupeViewer.steps);
  await page.click('#step');
  await waitFor(page, (s) => troupeViewer.steps === s + 1, stepsBefore);
  check(true, 'Step runs one step');

  // Selecting a robot opens its devices: sonar beams and live values.
  const at = await page.evaluate(() => troupeViewer.screenOf('b44'));
  await page.mouse.click(at.x, at.y);
  await waitFor(page, () => troupeViewer.selected === 'b44');
  await page.click('#step');  // while paused, one step brings the sensors' data
  await waitFor(page, () => troupeViewer.beams() > 0 && troupeViewer.values()['b44/ranger:0']);
  // The panel refreshes a few times a second.
  await waitFor(page, () => document.querySelector('#devices li[data-device="b44/ranger:0"]')?.textContent
                                .includes('ranges'));
  const shown = await page.locator('#devices li[data-device]').allTextContents();
  check(shown.some((t) => t.startsWith('b44/ranger:0') && t.includes('ranges')), 'the panel shows the sonar ring',
        shown.join(' | '));
  check(shown.some((t) => t.startsWith('b44/fiducial:0')), 'the panel shows the fiducial finder');

  // Dragging b44 teleports it to where it was dropped.
  const from = await page.evaluate(() => troupeViewer.screenOf('b44'));
  const to = { x: from.x + 70, y: from.y - 45 };
  const target = await page.evaluate(([x, y]) => troupeViewer.worldAt(x, y), [to.x, to.y]);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(to.x, to.y, { steps: 12 });
  await page.mouse.up();
  await waitFor(page, () => troupeViewer.teleports === 1);
  const moved = JSON.parse((await run(troupe, ['req', `127.0.0.1:${sim.port}`, 'simulation:0', 'getpose', 'b44']))
                             .replace(/^[^{]*/, '')).pose;
  check(Math.hypot(moved.x - target.x, moved.y - target.y) < 0.01, 'the dragged robot is where it was dropped',
        `dropped at ${target.x.toFixed(3)}, ${target.y.toFixed(3)}; ground truth ${moved.x}, ${moved.y}`);
  check(Math.hypot(moved.x - truth.pose.x, moved.y - truth.pose.y) > 0.5, 'and it moved');
  await page.click('#pause');  // running again for the picture's trails and beams
  await waitFor(page, (s) => troupeViewer.steps > s + 5, await page.evaluate(() => troupeViewer.steps));
  await page.screenshot({ path: join(args.out, 'viewer-sim.png') });
  console.log(`screenshot: ${join(args.out, 'viewer-sim.png')}`);

  // Garbage on another WebSocket: that one is closed with a reason, the page
  // goes on.
  const closed = await page.evaluate(() => new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.onopen = () => ws.send(new Uint8Array([0xde, 0xad, 0xbe, 0xef, 1, 2, 3]));
    ws.onclose = (e) => resolve({ code: e.code, reason: e.reason });
  }));
  check(closed.code === 1007, 'a WebSocket sending garbage is closed (1007)', JSON.stringify(closed));
  const before = await page.evaluate(() => troupeViewer.framesIn);
  await waitFor(page, (n) => troupeViewer.framesIn > n + 10, before);
  check(await page.evaluate(() => document.body.dataset.connected === 'true'), 'the page is still served');
  await page.close();
  sim.child.kill('SIGTERM');
}

/// The selected robot's blobs as the page draws them in the world view,
/// each with the canvas pixel (r, g, b) at its page position: read in one
/// go, between two frames.
function drawnBlobs(page) {
  return page.evaluate(() => {
    const c = document.getElementById('world');
    const box = c.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const ctx = c.getContext('2d');
    return troupeViewer.worldBlobs().map((b) => {
      const d = ctx.getImageData(Math.round((b.pageX - box.left) * dpr), Math.round((b.pageY - box.top) * dpr), 1, 1).data;
      return { ...b, rgb: [d[0], d[1], d[2]] };
    });
  });
}

/// True when `rgb` is the colour '#rrggbb' (within antialiasing).
function isColor(rgb, color) {
  const want = parseInt(color.slice(1), 16);
  return [want >> 16, (want >> 8) & 255, want & 255].every((c, i) => Math.abs(c - rgb[i]) < 40);
}

/// Waits for the next frames to be drawn.
function frames(page, n = 3) {
  return page.evaluate((n) => new Promise((resolve) => {
    const tick = () => (--n <= 0 ? resolve() : requestAnimationFrame(tick));
    requestAnimationFrame(tick);
  }), n);
}

// The world divided between two processes under mpirun: the page draws
// every robot, each where the leader's ground truth has it, and robots
// driven on both sides of the cut move on the page as they do in the world.
async function dividedPage(browser) {
  if (!args.mpirun) {
    console.log('note: troupe-sim was built without MPI; the divided world part is skipped');
    return;
  }
  // OpenMPI refuses root unless told twice (CI runs as root).
  if (process.getuid() === 0) {
    process.env.OMPI_ALLOW_RUN_AS_ROOT = '1';
    process.env.OMPI_ALLOW_RUN_AS_ROOT_CONFIRM = '1';
  }
  const troupe = join(args.bin, 'troupe');
  const sim = await start(args.mpirun,
                          ['--oversubscribe', '-np', '2', join(args.bin, 'troupe-sim'),
                           join(args.source, 'examples/worlds/swarm100.world'), '--no-ctrl', '--port', '0',
                           '--view', '0', '--paused'],
                          { port: /listening on [^\n]*:(\d+)\n/, url: /viewer at (\S+)\n/ });
  const host = `127.0.0.1:${sim.port}`;
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  page.on('pageerror', (e) => check(false, 'divided: no error on the page', e.message));
  await page.goto(sim.url);
  await waitFor(page, () => window.troupeViewer?.ready);
  const drawn = await page.evaluate(() => troupeViewer.robots().filter((n) => troupeViewer.pose(n) !== null));
  check(drawn.length === 100, 'divided over 2 ranks: the page draws all 100 robots', `${drawn.length}`);

  // b0 (x = -8.1) and b99 (x = 8.6) stand on either side of the cut at x = 0.
  const truth = async (robot) => JSON.parse((await run(troupe, ['req', host, 'simulation:0', 'getpose', robot]))
                                              .replace(/^[^{]*/, '')).pose;
  const start0 = await truth('b0');
  await run(troupe, ['cmd', host, 'b0/position2d:0', 'vel', '0.4', '0', '0']);
  await run(troupe, ['cmd', host, 'b99/position2d:0', 'vel', '0.4', '0', '0.5']);
  await run(troupe, ['req', host, 'simulation:0', 'step', '20']);
  for (const robot of ['b0', 'b99']) {
    const at = await truth(robot);
    await waitFor(page, ([name, x, y]) => {
      const p = troupeViewer.pose(name);
      return p && Math.hypot(p.x - x, p.y - y) < 1e-3;
    }, [robot, at.x, at.y]);
    check(true, `divided: ${robot} is drawn where the world moved it`, JSON.stringify(at));
  }
  const moved = await truth('b0');
  check(Math.hypot(moved.x - start0.x, moved.y - start0.y) > 0.2, 'divided: b0 drove', 
        `${JSON.stringify(start0)} -> ${JSON.stringify(moved)}`);
  await page.screenshot({ path: join(args.out, 'viewer-divided.png') });
  await page.close();
  sim.child.kill('SIGTERM');
}

async function blobsAndRestartPage(browser) {
  const world = join(args.source, 'tests/viewer/blobs.world');
  const simArgs = (viewPort) => [world, '--port', '0', '--view', String(viewPort)];
  const patterns = { port: /listening on [^\n]*:(\d+)\n/, url: /viewer at (\S+)\n/ };
  let sim = await start(join(args.bin, 'troupe-sim'), simArgs(0), patterns);
  const viewPort = new URL(sim.url).port;
  const page = await browser.newPage({ viewport: { width: 1000, height: 760 } });
  page.on('pageerror', (e) => check(false, 'no error on the page', e.message));
  await page.goto(sim.url);
  await waitFor(page, () => window.troupeViewer?.ready);

  // The blobs of seer's blobfinder, drawn where the boxes are.
  const boxes = { '#ff0000': { x: 3.0, y: 0.8 }, '#0000ff': { x: 4.0, y: -1.0 } };
  const seeBlobs = async (when) => {
    await page.evaluate(() => troupeViewer.select('seer'));
    await waitFor(page, () => troupeViewer.worldBlobs().length === 2);
    await frames(page);
    const blobs = await drawnBlobs(page);
    for (const b of blobs) {
      const box = boxes[b.color];
      check(box && Math.hypot(b.x - box.x, b.y - box.y) < 0.35, `${when}: the ${b.color} blob is drawn at its box`,
            `${b.x.toFixed(2)}, ${b.y.toFixed(2)} m; box at ${box ? `${box.x}, ${box.y}` : '?'}`);
      check(isColor(b.rgb, b.color), `${when}: the canvas shows the ${b.color} blob there`, `pixel ${b.rgb}`);
    }
    return blobs;
  };
  const blobs = await seeBlobs('blobs');
  await page.screenshot({ path: join(args.out, 'viewer-blobs.png') });
  console.log(`screenshot: ${join(args.out, 'viewer-blobs.png')}`);
  // Not selected, seer's blobs are not drawn: those pixels were the blobs'.
  await page.evaluate(() => troupeViewer.select(''));
  await frames(page);
  for (const b of blobs) {
    const rgb = await page.evaluate(({ x, y }) => {
      const c = document.getElementById('world');
      const box = c.getBoundingClientRect();
      const dpr = window.devicePixelRatio || 1;
      const d = c.getContext('2d').getImageData(Math.round((x - box.left) * dpr), Math.round((y - box.top) * dpr), 1, 1).data;
      return [d[0], d[1], d[2]];
    }, { x: b.pageX, y: b.pageY });
    check(!isColor(rgb, b.color), `deselected: no ${b.color} blob drawn`, `pixel ${rgb}`);
  }

  // The simulator dies behind the open page: the page says so and retries.
  sim.child.kill('SIGKILL');
  await waitFor(page, () => troupeViewer.link !== 'open' && /reconnecting in/.test(
                                document.getElementById('status').textContent));
  const status = await page.textContent('#status');
  check(/disconnected: .*reconnecting in [\d.]+ s \(attempt \d+\)/.test(status),
        'simulator killed: the page shows it is reconnecting', status);
  await page.waitForTimeout(1500);  // a few failed attempts, the backoff growing
  const attempts = await page.evaluate(() => document.getElementById('status').textContent);
  check(/attempt [2-9]/.test(attempts), 'it keeps trying', attempts);
  // Restarted on the same viewer port, it is found again without a reload.
  sim = await start(join(args.bin, 'troupe-sim'), simArgs(viewPort), patterns);
  await waitFor(page, () => troupeViewer.opens === 2 && troupeViewer.ready && troupeViewer.link === 'open');
  const names = await page.evaluate(() => troupeViewer.robots());
  check(names.length === 1 && names[0] === 'seer', 'simulator restarted: the page shows its robot again',
        names.join(', '));
  await waitFor(page, () => /^connected: /.test(document.getElementById('status').textContent));
  check(/connected: troupe-sim, 1 robots \(reconnected 1×\)/.test(await page.textContent('#status')),
        'the status line says it reconnected', await page.textContent('#status'));
  await seeBlobs('after the restart');
  await page.close();
  sim.child.kill('SIGTERM');
}

/// troupe-sim serving `world` paused, with its viewer, and a page on that:
/// { sim, page, addr } (addr: the simulator's wire port).
async function pausedSimPage(browser, world, what) {
  const sim = await start(join(args.bin, 'troupe-sim'), [join(args.source, world), '--port', '0', '--view', '0', '--paused'],
                          { port: /listening on [^\n]*:(\d+)\n/, url: /viewer at (\S+)\n/ });
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  page.on('pageerror', (e) => check(false, `${what}: no error on the page`, e.message));
  await page.goto(sim.url);
  return { sim, page, addr: `127.0.0.1:${sim.port}` };
}

// A RoboCup match: the field, the ball as a disc, the score and a kick.
async function matchPage(browser) {
  const troupe = join(args.bin, 'troupe');
  const { sim, page, addr } = await pausedSimPage(browser, 'examples/robocup/match.world', 'match');
  await waitFor(page, () => window.troupeViewer?.ready);
  const names = await page.evaluate(() => troupeViewer.robots());
  check(names.length === 9 && names[8] === 'ball', 'match: 8 robots and the ball', names.join(' '));
  const field = await page.evaluate(() => troupeViewer.field());
  check(field && field.length === 9 && field.width === 5, 'match: the field comes with the models', JSON.stringify(field));
  await waitFor(page, () => troupeViewer.colorAt(2, -2) === '#3f8f3f');
  check(true, 'match: the grass is drawn');
  // A goal for blue: the ball behind the yellow goal line, one step.
  await run(troupe, ['req', addr, 'simulation:0', 'setpose', 'ball', '4.8', '0', '0']);
  await run(troupe, ['req', addr, 'simulation:0', 'step', '2']);
  await waitFor(page, () => troupeViewer.game()?.blue === 1);
  check(true, 'match: the score shows the goal');
  // A kick: yellow3's kicker goes out for a quarter of a second.
  await run(troupe, ['cmd', addr, 'yellow3/actuator:0', 'kick']);
  await run(troupe, ['req', addr, 'simulation:0', 'step', '3']);
  await waitFor(page, () => troupeViewer.kicking().includes('yellow3'));
  check(true, 'match: the kick is shown');
  await page.screenshot({ path: join(args.out, 'viewer-match.png') });
  console.log(`screenshot: ${join(args.out, 'viewer-match.png')}`);
  await page.close();
  sim.child.kill('SIGTERM');
}

// The selected robot's camera in the panel: the page asks for PNG and the
// browser decodes it; the canvas pixels must be the camera's own, as a
// wire client (`troupe echo --json`, raw rows) reads them at the same
// paused step. A robot without a camera shows no image.
async function cameraPage(browser) {
  const troupe = join(args.bin, 'troupe');
  const { sim, page, addr } = await pausedSimPage(browser, 'examples/worlds/camera.world', 'camera');
  await waitFor(page, () => window.troupeViewer?.ready);
  // Selecting cam opens its devices, cam/camera:0 with PNG asked; one step renders an image.
  await page.evaluate(() => troupeViewer.select('cam'));
  await waitFor(page, () => /camera:0/.test(document.getElementById('devices')?.textContent ?? ''));
  await run(troupe, ['req', addr, 'simulation:0', 'step', '1']);
  await waitFor(page, () => document.querySelector('#devices canvas.camera') !== null);
  const shown = await page.locator('#devices li[data-device="cam/camera:0"]').textContent();
  check(/160x120 Rgb8, Png, \d+ bytes/.test(shown), 'camera: the page gets PNG images', shown);
  const raw = JSON.parse(await run(troupe, ['echo', addr, 'cam/camera:0', '--json', '--count', '1'])).body;
  check(raw.width === 160 && raw.height === 120 && raw.stride === 480 && raw.data.length === 57600,
        'camera: a wire client reads the raw image', `${raw.width}x${raw.height} stride ${raw.stride}`);
  // Points across the image: the sky, the walls, the floor, the boxes.
  const points = [[0, 0], [80, 60], [20, 100], [150, 30], [60, 70], [78, 68], [114, 50], [159, 119], [45, 55]];
  const drawn = await page.evaluate((pts) => {
    const c = document.querySelector('#devices canvas.camera');
    const g = c.getContext('2d');
    return { width: c.width, height: c.height, px: pts.map(([x, y]) => [...g.getImageData(x, y, 1, 1).data.slice(0, 3)]) };
  }, points);
  check(drawn.width === 160 && drawn.height === 120, 'camera: the panel draws the image at its size',
        `${drawn.width}x${drawn.height}`);
  const distinct = new Set();
  points.forEach(([x, y], i) => {
    const at = y * raw.stride + 3 * x;
    const want = [raw.data[at], raw.data[at + 1], raw.data[at + 2]];
    distinct.add(want.join(','));
    check(want.every((v, k) => v === drawn.px[i][k]), `camera: pixel (${x}, ${y}) is the camera's`,
          `page ${drawn.px[i]} wire ${want}`);
  });
  check(distinct.size >= 3, 'camera: the points see different things', [...distinct].join(' '));
  await page.screenshot({ path: join(args.out, 'viewer-camera.png') });
  // The visitor has no camera: no image in its panel.
  await page.evaluate(() => troupeViewer.select('visitor'));
  await waitFor(page, () => document.querySelector('#selected h2')?.textContent === 'visitor');
  check(await page.locator('#devices canvas.camera').count() === 0, 'camera: no image for a robot without a camera');
  await page.close();
  sim.child.kill('SIGTERM');
}

async function nodePage(browser, config, name, drive) {
  const node = await start(args.node, [config, '--port', '0'], { port: /serving \d+ devices on [^\n]*:(\d+)\n/ });
  const view = await start(join(args.bin, 'troupe-view'), [`127.0.0.1:${node.port}`, '--http-port', '0'],
                           { url: /viewer at (\S+)/ });
  if (drive) await drive(node.port);
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  page.on('pageerror', (e) => check(false, 'no error on the page', e.message));
  await page.goto(view.url);
  await waitFor(page, () => window.troupeViewer?.ready);
  check(await page.evaluate(() => troupeViewer.mode) === 'node', `${name}: the page knows it is a node`);
  const devices = await page.evaluate(() => troupeViewer.devices());
  check(devices.includes('position2d:0'), `${name}: its devices are listed`, devices.join(', '));
  const robot = (await page.evaluate(() => troupeViewer.robots()))[0];
  await waitFor(page, (r) => troupeViewer.trailLength(r) > 5, robot);
  check(true, `${name}: the odometry trail grows`);
  await waitFor(page, () => document.querySelector('#devices li[data-device="position2d:0"]')?.textContent
                                .includes('odometry'));
  const shown = await page.locator('#devices li[data-device="position2d:0"]').textContent();
  check(shown.includes('odometry'), `${name}: position2d:0's live values are shown`, shown);
  return { node, view, page };
}

const browser = await chromium.launch({
  executablePath: kChromium,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const scratch = mkdtempSync(join(tmpdir(), 'troupe-viewer-'));
try {
  await simulatorPage(browser);
  await dividedPage(browser);
  await blobsAndRestartPage(browser);
  await matchPage(browser);
  await cameraPage(browser);

  // A kinematic base, driven in a circle over the wire.
  const troupe = join(args.bin, 'troupe');
  const kin = await nodePage(browser, join(args.source, 'examples/nodes/kinematic.json'), 'kinematic node',
                             (port) => run(troupe, ['cmd', `127.0.0.1:${port}`, 'position2d:0', 'vel', '0.5', '0', '0.6']));
  await kin.page.screenshot({ path: join(args.out, 'viewer-node.png') });
  // The node restarts behind troupe-view: the page reconnects through it.
  kin.node.child.kill('SIGKILL');
  await waitFor(kin.page, () => troupeViewer.link !== 'open');
  await start(args.node, [join(args.source, 'examples/nodes/kinematic.json'), '--port', kin.node.port],
              { port: /serving \d+ devices on [^\n]*:(\d+)\n/ });
  await waitFor(kin.page, () => troupeViewer.opens >= 2 && troupeViewer.ready && troupeViewer.link === 'open');
  const devices = await kin.page.evaluate(() => troupeViewer.devices());
  check(devices.includes('position2d:0'), 'node restarted: the page lists its devices again', devices.join(', '));
  await kin.page.close();

  // A recorded robot: a CARMEN log's odometry and laser.
  const log = args.shared ? join(args.shared, 'carmen/aces-corrected.log.gz') : '';
  if (log && existsSync(log)) {
    const config = join(scratch, 'replay.json');
    writeFileSync(config, JSON.stringify({
      name: 'replay', listen: '127.0.0.1', port: 0,
      drivers: [{ driver_type: 'logreplay', driver: { file: log, speed: 4.0, odometry: 'Corrected' },
                  provides: ['position2d:0', 'ranger:0', 'position2d:1'] }],
    }));
    const replay = await nodePage(browser, config, 'log replay node');
    await waitFor(replay.page, () => troupeViewer.beams() > 100);
    await waitFor(replay.page, () => document.querySelector('#devices li[data-device="ranger:0"]')?.textContent
                                       .includes('ranges'));
    const laser = await replay.page.locator('#devices li[data-device="ranger:0"]').textContent();
    check(/\d+ ranges/.test(laser), 'log replay node: the laser scan is shown', laser);
    await replay.page.screenshot({ path: join(args.out, 'viewer-log.png') });
  } else {
    console.log(`note: ${log || 'the shared data'} is absent; the CARMEN log part is skipped`);
  }
} catch (e) {
  check(false, 'the run', e.stack || e.message);
} finally {
  await browser.close();
  for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
  rmSync(scratch, { recursive: true, force: true });
}
console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
