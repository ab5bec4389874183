// The legend's line on the light between the mesh's vertices: linear interpolation, within the
// bound the server refined its mesh to, or unbounded where it did not refine (`serve`'s default
// fans). From /stats "mesh.tolerance" (docs/API.md), so the page never claims more than the server did.
export function meshBoundText(tolerance) {
  if (tolerance > 0) {
    const percent = Number((tolerance * 100).toPrecision(3));
    return `Between vertices the light is interpolated, refined until within ${percent}% of each light's local ` +
      'unshadowed level at the test points.';
  }
  return 'Between vertices the light is interpolated and not refined: inside a penumbra it can be off by several ' +
    'percent (a server started with --mesh-tolerance 0.005 refines it).';
}

export function installMeshBound({ hub }) {
  const line = document.getElementById('mesh-bound');
  hub.on('built', (stats, rebuilt) => {
    const tolerance = !rebuilt && stats && stats.mesh ? stats.mesh.tolerance : undefined;
    if (typeof tolerance !== 'number') return;  // a rebuild's report: the bound is the server's, unchanged
    line.textContent = meshBoundText(tolerance);
    line.hidden = false;
  });
}
