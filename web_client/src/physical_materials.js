// A scene material (scene JSON v1, SCENE_FORMAT.md "materials") as the parameters of three.js's
// MeshPhysicalMaterial: the glossy and transmissive part the page draws over the DM's vertex
// colours (README "The page"). Pure functions, no three.js objects.

// Scene defaults (core/scene/scene.h Material): aluminium, α 0.5, ior 1.5.
const DEFAULT_ETA = [1.657, 0.880, 0.521];
const DEFAULT_K = [9.224, 6.270, 4.837];
const DEFAULT_ALPHA = 0.5;
const DEFAULT_IOR = 1.5;
const THREE_IOR = [1, 2.333]; // MeshPhysicalMaterial.ior's range

// Normal-incidence reflectance of a conductor with complex index eta + i·k (per channel).
export function conductorF0(eta, k) {
  return eta.map((n, c) => ((n - 1) ** 2 + k[c] ** 2) / ((n + 1) ** 2 + k[c] ** 2));
}

// three.js roughness r has GGX α = r²; its anisotropy a stretches the tangent's α to
// mix(r², 1, a²) (lights_physical_fragment.glsl), so [αx, αy] is r = √min, a from the larger,
// turned onto the rougher axis (the tangent is the face's first edge, as core/render's frame).
export function roughnessOf(roughness) {
  const [ax, ay] = (Array.isArray(roughness) ? roughness : [roughness ?? DEFAULT_ALPHA, roughness ?? DEFAULT_ALPHA])
    .map((a) => Math.min(1, Math.max(0, a)));
  const lo = Math.min(ax, ay), hi = Math.max(ax, ay);
  return {
    roughness: Math.sqrt(lo),
    anisotropy: hi > lo ? Math.sqrt((hi - lo) / (1 - lo)) : 0,
    anisotropyRotation: ax >= ay ? 0 : Math.PI / 2,
  };
}

// MeshPhysicalMaterial parameters for a material JSON, or null when the DM's vertex colours show
// it whole: `diffuse` (Lambertian) and `rough_diffuse` (its facets are Lambertian; no specular lobe).
export function physicalParameters(material) {
  const type = (material && material.type) || 'diffuse';
  if (type === 'conductor') {
    const eta = material.eta || DEFAULT_ETA, k = material.k || DEFAULT_K;
    return { type, metalness: 1, color: conductorF0(eta, k), transmission: 0, ior: DEFAULT_IOR, ...roughnessOf(material.roughness) };
  }
  if (type === 'dielectric') {
    const ior = material.ior ?? DEFAULT_IOR;
    return { type, metalness: 0, color: [1, 1, 1], transmission: 1,
      ior: Math.min(THREE_IOR[1], Math.max(THREE_IOR[0], ior)), ...roughnessOf(material.roughness) };
  }
  return null;
}

// True when some object of the scene JSON has a material physicalParameters draws.
export function hasPhysicalMaterials(scene) {
  const materials = scene.materials || {};
  return scene.objects.some((o) => o.material && physicalParameters(materials[o.material]));
}
