"""Scene generators: the procedural interiors, the sky, the terrain meshes, the textured
room's assets and the contact sheet of the shipped scenes."""
