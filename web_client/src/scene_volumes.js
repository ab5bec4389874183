// A scene file with volumes, loaded from the page: the server reads volume files only from scene
// files it was started on, never from a scene sent as JSON (a client must not name the server's
// files: 422 at objects[i].file). So the page takes the scene's .nrrd files picked with it, sends
// the scene without its volumes, then uploads each volume (POST …/volumes, under its own id,
// isovalue and material) and moves it to the file's transform: the scene as the file describes it.

const isVolume = (object) => object && object.type === 'volume';
const baseName = (path) => String(path).split(/[\\/]/).pop();

// sceneText and the picked .nrrd Files → {text: the scene without its volumes, volumes: [{object,
// file}]}; throws an Error naming the key path of a volume whose file was not picked (nothing is
// sent then). A scene without volumes comes back as it was.
export function splitVolumes(sceneText, nrrdFiles) {
  let scene;
  try {
    scene = JSON.parse(sceneText);
  } catch {
    return { text: sceneText, volumes: [] }; // the server names what is wrong with it
  }
  const objects = Array.isArray(scene && scene.objects) ? scene.objects : [];
  if (!objects.some(isVolume)) {
    if (nrrdFiles.length) throw new Error('the .nrrd files go with a scene that has volume objects; this one has none');
    return { text: sceneText, volumes: [] };
  }
  const byName = new Map(nrrdFiles.map((file) => [file.name, file]));
  const volumes = [];
  objects.forEach((object, index) => {
    if (!isVolume(object)) return;
    const file = byName.get(baseName(object.file));
    if (!file) {
      throw new Error(`the scene's volume '${object.id}' reads ${object.file}: pick that .nrrd file together with the scene `
        + `(nothing was loaded; at objects[${index}].file)`);
    }
    volumes.push({ object, file });
  });
  return { text: JSON.stringify({ ...scene, objects: objects.filter((o) => !isVolume(o)) }), volumes };
}

// Adds the volumes to the created scene: one upload and one move each.
export async function addVolumes(api, sceneId, volumes) {
  for (const { object, file } of volumes) {
    const query = new URLSearchParams({ id: object.id, name: file.name });
    if (object.isovalue !== undefined) query.set('isovalue', String(object.isovalue));
    if (object.material !== undefined) query.set('material', object.material);
    await api.request('POST', `${api.scenePath(sceneId)}/volumes?${query}`,
      { body: file, headers: { 'Content-Type': 'application/octet-stream' } });
    if (object.transform) await api.postEdits(sceneId, { edits: [{ op: 'move', id: object.id, transform: object.transform }] });
  }
}
