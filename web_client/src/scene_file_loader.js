// "Load a scene": the files chosen in the file input become a new served scene, then the page
// switches to it (?scene=ID). A .scene.json is posted as is (POST /api/scenes; its volumes, picked
// with it, uploaded after: scene_volumes.js); an .obj (with the
// .mtl files picked together), .gltf or .glb is posted as a form to POST /api/scenes?format=...
// (docs/API.md), with the page's scale and light-radiance options. The server names the key path
// of any problem; the import report (what was repaired) is kept for the next page in
// sessionStorage and shown there by import_report_panel.js.
import { BuildProgress, newTicket } from './build_progress.js';
import { storeImportReport } from './import_report_panel.js';
import { addVolumes, splitVolumes } from './scene_volumes.js';

const kinds = [
  [/\.json$/i, 'scene'],
  [/\.obj$/i, 'obj'],
  [/\.mtl$/i, 'mtl'],
  [/\.gltf$/i, 'gltf'],
  [/\.glb$/i, 'glb'],
  [/\.nrrd$/i, 'nrrd'],
];

function kindOf(file) {
  const match = kinds.find(([pattern]) => pattern.test(file.name));
  return match ? match[1] : null;
}

// The files picked → {main, mtl[], nrrd[]}; throws with a message the banner shows.
export function classifyFiles(files) {
  const main = [];
  const mtl = [];
  const nrrd = [];
  for (const file of files) {
    const kind = kindOf(file);
    if (!kind) throw new Error(`cannot load '${file.name}': choose a .scene.json (+ its .nrrd volumes), .obj (+ .mtl), .gltf or .glb file`);
    if (kind === 'mtl') mtl.push(file);
    else if (kind === 'nrrd') nrrd.push(file);
    else main.push({ file, kind });
  }
  if (main.length !== 1) {
    throw new Error(main.length ? `choose one scene file at a time, got ${main.map((m) => m.file.name).join(', ')}`
      : 'the .mtl files need their .obj: pick them together');
  }
  if (mtl.length && main[0].kind !== 'obj') throw new Error('.mtl files go with an .obj only');
  if (nrrd.length && main[0].kind !== 'scene') throw new Error('.nrrd files go with a .scene.json only');
  return { main: main[0], mtl, nrrd };
}

// The import options typed in the page → query parameters (empty fields: the file's own values).
export function importQuery(kind, name, scaleText, radianceText, ticket) {
  const params = new URLSearchParams({ format: kind, name });
  if (ticket) params.set('ticket', ticket);
  if (scaleText.trim()) params.set('scale', scaleText.trim());
  if (radianceText.trim()) params.set('light_radiance', radianceText.replace(/\s+/g, ''));
  return params;
}

function importFile(api, main, mtl, options, onProgress, ticket) {
  const form = new FormData();
  form.append('file', main.file, main.file.name);
  for (const file of mtl) form.append('mtl', file, file.name);
  const query = importQuery(main.kind, main.file.name, options.scale.value, options.radiance.value, ticket);
  return api.upload(`/api/scenes?${query}`, form, null, onProgress);
}

// Upload progress, then the server's build (its stage, fraction and seconds: build_progress.js).
function uploadProgress(loading, fileName, build) {
  return (sent, total, done) => {
    if (done) build.start();
    else if (!build.running) loading.bytes(`Uploading ${fileName}`, sent, total);
  };
}

// options: {scale, radiance}: the page's input elements for the import options; loading: the
// LoadingIndicator that shows the upload and the build.
export function installSceneFileLoader(input, api, onError, options, loading) {
  input.addEventListener('change', async () => {
    const files = input.files ? [...input.files] : [];
    if (!files.length) return;
    let build = null;
    try {
      const { main, mtl, nrrd } = classifyFiles(files);
      const ticket = newTicket();
      build = new BuildProgress(api, loading, ticket);
      const progress = uploadProgress(loading, main.file.name, build);
      let created;
      if (main.kind === 'scene') {
        const name = main.file.name.replace(/\.scene\.json$|\.json$/i, '');
        const { text, volumes } = splitVolumes(await main.file.text(), nrrd);
        created = await api.createScene(text, name, progress, ticket);
        build.stop();
        if (volumes.length) loading.step(`Adding ${volumes.length} volume(s)…`);
        await addVolumes(api, created.id, volumes);
      } else {
        created = await importFile(api, main, mtl, options, progress, ticket);
        build.stop();
        storeImportReport(created.id, created.name, created.import);
      }
      loading.step('Opening the new scene…');
      const next = new URLSearchParams({ scene: created.id });
      if (api.token) next.set('token', api.token); // the new scene's page keeps the token
      window.location.search = `?${next}`;
    } catch (error) {
      if (build) build.stop();
      loading.cancel();
      if (error.code !== 'build_cancelled') onError(error);
    } finally {
      input.value = '';
    }
  });
}
