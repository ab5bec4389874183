// The import report of a scene this browser tab imported (POST /api/scenes?format=...): what the
// file held and every repair the importer made (README "Import and export"), shown in the panel
// of that scene's page. Kept per tab in sessionStorage, since loading a scene reloads the page.

const storageKey = (sceneId) => `penumbra.import-report.${sceneId}`;

// sceneName guards against a restarted server that gave the id to another scene.
export function storeImportReport(sceneId, sceneName, report) {
  if (!report) return;
  try {
    sessionStorage.setItem(storageKey(sceneId), JSON.stringify({ sceneName, report }));
  } catch {
    // Storage full or disabled: the scene still loads, only its report is not shown.
  }
}

export function storedImportReport(sceneId, sceneName) {
  try {
    const stored = JSON.parse(sessionStorage.getItem(storageKey(sceneId)) || 'null');
    return stored && stored.sceneName === sceneName ? stored.report : null;
  } catch {
    return null;
  }
}

const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;

// Fills `root` (hidden when this tab did not import the scene) and returns the report.
export function showImportReport(root, sceneId, sceneName) {
  const report = storedImportReport(sceneId, sceneName);
  root.replaceChildren();
  root.hidden = !report;
  if (!report) return null;
  const line = (text, className) => {
    const div = document.createElement('div');
    div.textContent = text;
    if (className) div.className = className;
    root.append(div);
    return div;
  };
  const seconds = typeof report.seconds === 'number' ? `, read in ${(report.seconds * 1000).toFixed(1)} ms` : '';
  line(`Imported ${report.source} (${report.format}): ${plural(report.objects, 'object')}, ` +
    `${plural(report.faces, 'face')}, ${plural(report.lights, 'light')}, ${plural(report.materials, 'material')}${seconds}`);
  // A file without lights went into the default studio: where, and at what scale.
  if (report.studio && report.studio.sentence) line(report.studio.sentence, 'studio');
  // Each object's surface: components, closed ones, faces flipped, vertices welded.
  const meshes = report.meshes || [];
  for (const mesh of meshes.slice(0, 20)) {
    let text = `${mesh.object}: ${plural(mesh.faces, 'face')}, ${plural(mesh.components, 'component')}, ${mesh.closed_components} closed`;
    if (mesh.faces_flipped) text += `; ${plural(mesh.faces_flipped, 'face')} flipped`;
    if (mesh.vertices_welded) text += `; ${mesh.vertices_welded} vertices welded`;
    if (mesh.non_manifold_edges) text += `; ${plural(mesh.non_manifold_edges, 'non-manifold edge')} left`;
    line(text, 'mesh');
  }
  if (meshes.length > 20) line(`… and ${meshes.length - 20} more objects`, 'muted');
  const repairs = Object.entries(report.repairs || {});
  if (!repairs.length) line('no repairs were needed', 'muted');
  else {
    const list = document.createElement('ul');
    list.className = 'repairs';
    for (const [name, count] of repairs) {
      const item = document.createElement('li');
      item.dataset.repair = name;
      item.textContent = `${name.replaceAll('_', ' ')}: ${count}`;
      list.append(item);
    }
    root.append(list);
  }
  for (const warning of report.warnings || []) line(`warning: ${warning}`, 'warning');
  return report;
}
