// The panel's selection line ("selected box3") and the buttons that act on a selection
// (Duplicate, Delete, Focus), enabled and titled for what is selected: a scene keeps at least one
// light, so its last one cannot be deleted.

const $ = (id) => document.getElementById(id);

// page: {hub, objects}.
export function installSelectionPanel({ hub, objects }) {
  hub.on('selection', (id) => {
    $('selection').textContent = id ? `selected ${id}` : 'click an object';
    const light = id && id.startsWith('light:') ? objects.lightJson.get(id.slice(6)) : null;
    for (const button of ['duplicate', 'delete', 'focus']) $(button).disabled = !id;
    const lastLight = !!light && objects.lightJson.size <= 1;
    $('delete').disabled ||= lastLight;
    $('delete').title = lastLight ? 'The scene\'s last light cannot be deleted' : 'Delete the selection (Delete)';
    $('duplicate').title = light ? 'Add a copy of this light beside it (Ctrl+D)' : 'Duplicate the selection (Ctrl+D)';
  });
}
