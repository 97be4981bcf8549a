"""The default machine description shipped with hipsim: parameters, xacro, URDF, closures."""
