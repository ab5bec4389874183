// "Load a scene file": a .scene.json chosen in the file input is posted as is (POST /api/scenes,
// so the server validates it and names the key path of any problem), then the page switches
// to the new scene (?scene=ID). OBJ / glTF import is not offered here yet.

export function installSceneFileLoader(input, api, onError) {
  input.addEventListener('change', async () => {
    const file = input.files && input.files[0];
    if (!file) return;
    try {
      const name = file.name.replace(/\.scene\.json$|\.json$/i, '');
      const text = await file.text();
      const created = await api.createScene(text, name);
      window.location.search = `?scene=${encodeURIComponent(created.id)}`;
    } catch (error) {
      onError(error);
    } finally {
      input.value = '';
    }
  });
}
