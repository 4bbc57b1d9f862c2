//! The wgpu renderer: pipelines, camera, meshes, lines, colour maps. Knows wgpu, never the engine.
