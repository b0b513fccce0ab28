"""What the teeth give: the mesh stiffness of every mesh along the ideal kinematics."""
