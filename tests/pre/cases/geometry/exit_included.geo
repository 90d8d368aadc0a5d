// The berm slope from a file that ends with Exit; (gmsh stops in it).
Include "exit_included_body.geo";
